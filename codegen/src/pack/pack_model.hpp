// The pack file: one battery pack's limits, wiring and device settings, read from YAML (firmware/app/packs/)
// with the register maps' strict reader, so every problem is an error at file:line:col.
//
// Schema (unknown and missing keys are errors; numbers are decimal, with a fraction where the unit has one):
//   pack: bq76952-evm                 name: lower case, digits and '-'; namespace fw::packs::<name with '_'>
//   description: ...                  one line
//   device: bq76952                   bq76952 | bq76907 | bq76905 | bq79616 | bq4050 (device.cpp: what each
//   has) chemistry: li-ion                 li-ion | lfp (names the OCV table; documentation only) cells: 16
//   cells per device (BQ79616: per board of the chain) cell_inputs: [1, 2, 3]            the device's cell
//   inputs the cells use, bottom first (input n measures
//                                     VCn - VCn-1); required when cells < the device's inputs
//   shunt_micro_ohm: 1000             sense resistor (devices with a current input)
//   current_unit_ma: 1                the device's user-amps unit: 0.1 | 1 | 10 | 100 (BQ769x2 DA
//   Configuration) thermistor: 103AT                 the cell thermistor (the device's default temperature
//   model) limits:                           the firmware's own limits (app/protection)
//     cell_overvoltage:      {trip_mv, clear_mv}
//     cell_undervoltage:     {trip_mv, clear_mv}
//     charge_overcurrent:    {trip_ma, clear_ma, debounce_scans, recover_scans}
//     discharge_overcurrent: {trip_ma (negative), clear_ma, debounce_scans, recover_scans, latch_trips,
//                             trip_decay_s}: latch_trips trips, each within trip_decay_s of the one before,
//                             latch the discharge path off until ClearFaults (both or neither)
//     charge_temperature:    {min_c, max_c, hysteresis_c}
//     discharge_temperature: {min_c, max_c, hysteresis_c}
//     stale_scans: 3                  data older than this many scan periods is stale
//     comm_loss_scans: 3              this many failed scans in a row is a lost link
//   device_protections:               the device's own protections (BQ769x2, BQ7690x): each one listed is
//     cov: {threshold_mv, delay_ms}   enabled and written; device.cpp lists every key, unit and step
//     ...
//   state_of_charge:
//     capacity_mah: 2500
//     full_cell_mv: 4200              highest cell at or above it (not discharging): 100 %
//     empty_cell_mv: 2750             lowest cell at or below it (not charging): 0 %
//     rest_current_ma: 50             |current| below it for rest_s: at rest
//     rest_s: 600
//     ocv_mv: [..11 values..]         the cell's open-circuit voltage at 0, 10, ..., 100 %
//     ocv_min_step_mv: 20             a 10 % step of the table must rise this much for a correction there
//   balancing: {start_delta_mv, stop_delta_mv, cell_hysteresis_mv, min_cell_mv, charge_current_ma,
//               rest_current_ma, rest_s, min_cell_temp_c, max_cell_temp_c, max_die_temp_c, min_dwell_s,
//               refused_backoff_s}
//   can: {base_id, period_ms, slow_every}
//   storage:                          pack storage (firmware/app/monitors/storage_mode.hpp); optional
//     scan_period_ms: 1000            the scan period in storage: whole 100 ms scan periods, 200..25000, and
//                                     shorter than the device's host watchdog
//     device_sleep: true              true | false: the device may SLEEP (BQ769x2, BQ7690x only)
//     auto_entry_min: 0               minutes at rest before storage begins on its own (0: by command only)
//     rest_current_ma: 50             optional: at rest at or below it (default: state_of_charge's)
// (Braces above abbreviate block mappings: the reader takes block mappings only.)
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "diag/diag.hpp"
#include "yaml/yaml.hpp"

namespace regmapgen::pack {

// A number as written, with where it was written. `present` false: the key is absent.
struct Quantity {
  double value = 0;
  std::int64_t integer = 0;
  bool isInteger = false;
  bool present = false;
  std::string text;
  Loc loc;
};

// A mapping of quantities by key, as written (the device_protections entries, limit rows).
struct Group {
  std::string key;
  Loc loc;
  bool present = false;
  std::map<std::string, Quantity> values;
  const Quantity& operator[](const std::string& k) const;
};

struct PackFile {
  int file = -1;
  Loc loc;  // the document
  std::string name;
  Loc nameLoc;
  std::string description;
  std::string device;
  Loc deviceLoc;
  std::string chemistry;
  Loc chemistryLoc;
  Quantity cells;
  std::vector<Quantity> cellInputs;  // empty: not given
  Loc cellInputsLoc;
  Quantity shuntMicroOhm;
  Quantity currentUnitMa;
  std::string thermistor;
  Loc thermistorLoc;
  // limits
  Group cellOvervoltage, cellUndervoltage, chargeOvercurrent, dischargeOvercurrent, chargeTemperature,
      dischargeTemperature;
  Quantity staleScans, commLossScans;
  Loc limitsLoc;
  // device_protections, in file order
  std::vector<Group> protections;
  Loc protectionsLoc;
  bool hasProtections = false;
  // state_of_charge
  Group soc;
  std::vector<Quantity> ocvMv;
  Loc ocvLoc;
  Group balancing;
  Group can;
  Group storage;  // its quantities; device_sleep is a word:
  std::string deviceSleep;
  Loc deviceSleepLoc;
};

// Reads the YAML of `file` (registered in `sources`) into a PackFile; every unknown key, missing key and
// malformed value goes to `diag`. Range and consistency checks are pack_check's.
PackFile readPack(const Sources& sources, int file, Diagnostics& diag);

}  // namespace regmapgen::pack
