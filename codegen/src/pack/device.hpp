// What each battery device can express, for the pack generator: its cell inputs, its current register and
// user-amps units, and the protections it has (the pack file's device_protections keys), each with the
// register-map entries that hold its threshold and delay and how their codes turn into physical values.
// Steps, ranges and widths come from the register map itself (regmaps/<family>/*.yaml); only what the map
// cannot say (a delay's offset in codes, a threshold table the map has no enum for) is written here, each
// with its TI source.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace regmapgen::pack {

// How a protection's threshold is written in the pack file and held by the device.
enum class ThresholdKind : uint8_t {
  None,          // no threshold (the host watchdog)
  CellMv,        // a cell voltage, mV: code x the entry's scale
  SenseCurrent,  // a current, mA, held as the sense-resistor voltage: code x the entry's scale in mV
  SenseTable,    // a current, mA, held as one of a table of sense-resistor voltages (mV by code)
  DegC,          // a temperature, degC: code x the entry's scale
};

// Which firmware limit a device protection backs up, and on which side of it the device must act.
enum class Backs : uint8_t {
  None,
  CellOvAbove,       // above limits.cell_overvoltage.trip_mv
  CellUvBelow,       // below limits.cell_undervoltage.trip_mv
  ChargeOcAbove,     // above limits.charge_overcurrent.trip_ma
  DischargeOcBelow,  // beyond limits.discharge_overcurrent.trip_ma (a larger discharge)
  ChargeOtAbove,     // above limits.charge_temperature.max_c
  DischargeOtAbove,  // above limits.discharge_temperature.max_c
  AnyOtAbove,        // above both max_c (opens both paths, or sees every sensor the firmware sees)
  ChargeUtBelow,     // below limits.charge_temperature.min_c
  DischargeUtBelow,  // below limits.discharge_temperature.min_c
  AnyUtBelow,        // below both min_c
};

struct ProtectionSpec {
  std::string key;    // device_protections key: cov, cuv, occ, ...
  std::string title;  // in messages
  ThresholdKind kind = ThresholdKind::None;
  std::string thresholdKey;    // threshold_mv, threshold_ma, threshold_c
  std::string thresholdEntry;  // data-memory entry (C++ name in the register map)
  std::vector<int> tableMv;    // SenseTable without an enum in the map: mV by code
  std::string delayKey;        // delay_ms, delay_us, delay_s, delay_scans, delay_code, timeout_s
  std::string delayEntry;
  double delayStep = 1;  // physical delay = (code + delayOffset) x delayStep (in the key's unit)
  int delayOffset = 0;
  std::vector<int> delayTable;  // or: the delay (in the key's unit) by code
  std::string enableEntry;      // Enabled Protections register (entry name) and its field
  std::string enableField;
  Backs backs = Backs::None;
  std::string source;  // the TI document the non-map facts come from
};

struct DeviceSpec {
  std::string name;               // bq76952, ...
  std::string family;             // register-map family: bq769x2, bq7690x, bq79616, bq4050
  std::string title;              // "BQ76952"
  int inputs = 0;                 // cell inputs
  bool current = false;           // has a current input (shunt, coulomb counter)
  std::string currentEntry;       // the command with the current reading (its type gives the range)
  std::vector<int> unitsTenthMa;  // user-amps units it can be set to, in 0.1 mA (empty: fixed 1 mA)
  bool settings = false;          // the firmware writes its start-up settings (CONFIG_UPDATE)
  bool stateOfCharge = false;     // the firmware counts its charge (the device has an accumulated charge)
  bool gauge = false;             // the device is a gas gauge with its own state of charge
  std::vector<ProtectionSpec> protections;
  // Where TI documents the SLEEP the firmware allows in pack storage (SLEEP_ENABLE / SLEEP_DISABLE); empty:
  // none the firmware controls (storage is the scan period only).
  std::string sleepSource;
};

// The devices a pack file may name; nullptr for an unknown name.
const DeviceSpec* findDevice(const std::string& name);
std::string deviceNames();

// BQ7690x Vcell Mode: the code for a set of used inputs (1-based, ascending), or -1 when the device has no
// such mode (SLUUCJ0 / SLUUCY8 Settings:Configuration:Vcell Mode).
int bq7690xVcellMode(int deviceInputs, const std::vector<int>& inputs);

}  // namespace regmapgen::pack
