// Checks a pack file against its device and the device's register map, and resolves it into what the
// firmware is built from: the firmware limit table, the device's start-up settings as register codes, the
// state-of-charge and balancing parameters.
//
// Contract
// - Every problem is an error at the file:line:col of the value that causes it, and the checker goes on, so
//   one run shows them all. Among them (each a test in tests/codegen/pack_test.cpp):
//     a current limit the device cannot report at the chosen user-amps unit (the rule could never trip);
//     a threshold or delay that is not a whole number of the register's steps, or outside its range;
//     a device protection inside the firmware limit it backs up (the device must be the backstop: it acts
//       only beyond the firmware's trip, so the firmware always acts first on a normal limit);
//     more cells than the device has inputs, or inputs the device cannot be told about (BQ7690x Vcell Mode);
//     a storage scan period that is no whole number of scan periods, or not shorter than the device's host
//       watchdog (the device would open the FETs between storage scans), device SLEEP on a device whose SLEEP
//       the firmware does not control or whose SLEEP measurement interval the map does not give, and an
//       automatic storage entry without a current input or rest threshold.
// - Steps, ranges, widths and enums come from the register map (`family`); device.hpp adds what the map
//   cannot say.
// - resolvePack() returns false when any error was reported; the Resolved is then incomplete.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "diag/diag.hpp"
#include "model/model.hpp"
#include "pack/device.hpp"
#include "pack/pack_model.hpp"

namespace regmapgen::pack {

// One row of the firmware limit table (fw::app::LimitRow).
struct LimitRow {
  std::string fault;  // FaultId enumerator
  std::int64_t trip = 0;
  std::int64_t clear = 0;
  int debounce = 1;
  int recover = 1;
  std::string action;  // Action enumerator
  std::string comment;
  int latchTrips = 0;  // 0: no latch (Rule::latchTrips)
  int tripDecayS = 0;
};

// One start-up setting: the data-memory entry and its value as C++ (a code of the entry's type).
struct SettingRow {
  std::string entry;  // C++ name in the family's dm namespace
  std::string value;  // C++ expression of the entry's value_type
  std::string comment;
};

struct Resolved {
  const DeviceSpec* device = nullptr;
  std::string name;   // as written (bq76952-evm)
  std::string ident;  // C++ namespace (bq76952_evm)
  std::string description;
  std::string chemistry;
  int cells = 0;
  std::vector<int> inputs;  // the device input (1-based) of each cell, bottom first
  std::int64_t currentLsbTenthMa = 10;
  std::int64_t shuntMicroOhm = 0;
  std::vector<LimitRow> limits;  // in FaultId order
  int staleScans = 3;
  int commLossScans = 3;
  std::vector<SettingRow> settings;
  // state of charge (device->stateOfCharge)
  bool soc = false;
  std::int64_t capacityMah = 0, fullCellMv = 0, emptyCellMv = 0, restCurrentMa = 0, restS = 0,
               ocvMinStepMv = 20;
  std::vector<std::int64_t> ocvMv;
  // balancing, by pack-file key
  bool balancing = false;
  std::map<std::string, std::int64_t> balancingValues;
  std::int64_t canBaseId = 0x100, canPeriodMs = 100, canSlowEvery = 10;
  // pack storage (storageScanEvery 0: none)
  std::int64_t storageScanEvery = 0, storageAutoEntryMin = 0, storageRestCurrentMa = 0, storageSleepS = 0;
  bool storageDeviceSleep = false;
};

// The firmware's scan period (firmware/app/protection/default_limits.hpp kScanPeriod), which the pack's
// *_scans counts and the storage scan period are counted in.
inline constexpr std::int64_t kScanPeriodMs = 100;

// `family` is the device's register map (nullptr when the device has none loaded: an error for devices whose
// settings the firmware writes).
bool resolvePack(const PackFile& pack, const Family* family, Resolved& out, Diagnostics& diag);

}  // namespace regmapgen::pack
