// The firmware protection limits an image starts from: its pack file's (BMS_PACK, firmware/app/packs/*.yaml,
// generated as fw::pack by regmapgen pack), inside the monitors' own limits.
//
// The rows come from the pack file, one per fault it sets (pack::kLimitRows); regmapgen checks them against
// the device (a current the device cannot report at its user-amps unit, a device protection inside a firmware
// limit: file:line:col errors) and writes each device protection outside them (pack::kDeviceSettings;
// tests/app/backstop_test.cpp checks the ordering on every image), so the firmware acts first and the device
// is the backstop. The EVM packs hold the Li-ion limits below; firmware/app/packs/README.md says what each
// value means.
//
// Actions: the path the fault endangers. Over-voltage, charge over-current and the charge temperature limits
// open the charge path (discharging relieves them and stays allowed); under-voltage, discharge over-current
// and the discharge temperature limits open the discharge path (charging stays allowed); stale data, lost
// communication and an open sense wire (the cells are not measured) open both. Li-ion cells may be charged
// only between 0 and 45 degC and discharged between -20 and 60 degC (the usual cell data-sheet window), so
// the charge limits lie inside the discharge ones.
//
// Recovery: a cell or temperature limit clears once the value is back past its clear threshold (the
// hysteresis: 100 mV, 200 mV, 5 degC), on the next scan that shows it. A current limit clears only while
// current flows the other way, for 3 s (30 scans): TI's OCC and OCD recovery (SLUUBY2B 5.2, Protections:OCC
// and OCD Recovery Threshold -200 / +200 mA, Protections:Recovery:Time 3 s): an over-current in charge ends
// with a discharge of more than 200 mA, one in discharge with a charge of more than 200 mA, so a charger or a
// load that is still there is not switched back on to trip again.
//
// Latch: repeated discharge over-currents latch the discharge path off (TI's OCDL, SLUUBY2B 5.2,
// Protections:OCDL): each trip counts one, one is forgiven every 10 s after the latest (TI's Counter Dec
// Delay default), and the third trip so counted latches (TI ships OCDL Latch Limit 0, off; 3 is the trip
// after the BQ7690x's smallest latch setting of two retries, SLUUCJ0 Protections:Current:Latch Limit). A
// latched over-current stays through its recovery until ClearFaults finds the current gone (no more than 200
// mA of discharge); the charge path stays available throughout (on a single-output image, below, the one
// output holds both off). Three trips each within 10 s of the one before latch (with the 3 s recovery between
// them, the third comes 6.4 s after the first at the soonest); a load that trips once every 10 s or more
// never latches.
//
// Latch: repeated discharge over-currents latch the discharge path off (TI's OCDL, SLUUBY2B 5.2,
// Protections:OCDL): each trip counts one, one is forgiven every 10 s after the latest (TI's Counter Dec
// Delay default), and the third trip so counted latches (TI ships OCDL Latch Limit 0, off; 3 is the trip
// after the BQ7690x's smallest latch setting of two retries, SLUUCJ0 Protections:Current:Latch Limit). A
// latched over-current stays through its recovery until ClearFaults finds the current gone (no more than 200
// mA of discharge); the charge path stays available throughout (on a single-output image, below, the one
// output holds both off). Three trips each within 10 s of the one before latch (with the 3 s recovery between
// them, the third comes 6.4 s after the first at the soonest); a load that trips once every 10 s or more
// never latches. The pack file sets both (discharge_overcurrent latch_trips, trip_decay_s; the EVM packs
// 3 and 10 s).
//
// Cell voltages and temperatures act on the first scan that shows them: the monitors already filter their
// readings (BQ769x2 per-cell averaging, BQ79616 26 Hz low-pass, BQ4050 gauge filtering), and a second sample
// would add a scan period of latency, past the budget "fault visible -> paths off within one scan period".
// Current waits for two samples (load steps are real but brief).
//
// The discharge over-current limit of the EVM packs, -30 A, lies inside what every monitor reports: a BQ769x2
// or BQ7690x CC2 reading in the 1 mA user unit and the BQ4050's Current() are 16-bit, down to -32 768 mA (a
// limit beyond that could never trip: regmapgen refuses it). The devices' over-current protections sit beyond
// it (BQ76952 OCD1 40 mV across the EVM's 1 mOhm shunt, 40 A).
//
// One constant table (in flash, referenced, never copied) for the 100 ms scan period every image uses.
#pragma once

#include <array>
#include <cstddef>

#include "app/protection/limit_table.hpp"
#include "app/protection/protection.hpp"
#include "packs/selected.hpp"

namespace fw::app {

inline constexpr Duration kScanPeriod = ms(100);
static_assert(pack::kStorage.scanPeriod == kScanPeriod,
              "regmapgen pack counts the storage scan period in the firmware's scan periods (kScanPeriodMs)");

namespace limits_detail {
// The pack's rows, then the one rule a pack file does not set: an intermittent link, 4 of the last
// rateWindow (10) scan attempts failed (a link that fails 40 % of its scans gives no data to trust); clears
// once none of the last 10 failed.
constexpr std::array<LimitRow, kFaultCount> table() {
  std::array<LimitRow, kFaultCount> t{};
  static_assert(std::size(pack::kLimitRows) == kFaultCount - 1, "the pack sets every fault but comm_rate");
  for (size_t i = 0; i < std::size(pack::kLimitRows); ++i)
    t[i] = pack::kLimitRows[i];
  t[kFaultCount - 1] = {FaultId::CommErrorRate, 4, 1, 1, 1, Action::AllOff, false};
  return t;
}
}  // namespace limits_detail

inline constexpr std::array<LimitRow, kFaultCount> kLimits = limits_detail::table();
constexpr bool everyFaultOnceInOrder() {
  for (uint8_t i = 0; i < kFaultCount; ++i)
    if (static_cast<uint8_t>(kLimits[i].fault) != i) return false;
  return true;
}
static_assert(everyFaultOnceInOrder(), "kLimits: one row per fault, in FaultId order");

constexpr ProtectionConfig makeDefaultLimits(Duration scanPeriod) {
  ProtectionConfig c{};
  for (const LimitRow& row : kLimits) {
    Rule& r = c.rules[static_cast<uint8_t>(row.fault)];
    r.trip = row.trip, r.clear = row.clear, r.debounce = row.debounce, r.recover = row.recover;
    r.action = row.action, r.enabled = true;
    r.latchTrips = row.latch ? 1 : row.latchTrips, r.tripDecayS = row.tripDecayS;
  }
  c.rateWindow = 10;
  c.staleAfter = scanPeriod * pack::kStaleScans;
  c.commLossScans = pack::kCommLossScans;
  return c;
}

inline constexpr ProtectionConfig kDefaultLimits = makeDefaultLimits(kScanPeriod);

// The limits of an image whose one fault output opens both paths at once (G3507-BQ4050: the MCU's fault
// output; G3507-BQ79616 too, though it measures no current). Such an image cannot keep the path that relieves
// a current fault open, so the current of the other direction that kDefaultLimits waits for can never flow:
// an over-current would hold the pack off until a reset. Here a current fault recovers on time instead: once
// no more than 200 mA flows in the tripped direction (none flows while the output is asserted) for the same
// 3 s, the output is released, and a load or charger that is still there trips it again two scans later, a
// retry every 3.2 s as TI's timed recoveries do (SLUUBY2B 5.2, SCD Recovery Time). The gauge's own
// per-direction protections (BQ4050 OCC/OCD on its CHG/DSG FETs, SLUUAQ3A) stay in force underneath.
constexpr ProtectionConfig makeSingleOutputLimits(Duration scanPeriod) {
  ProtectionConfig c = makeDefaultLimits(scanPeriod);
  Rule& occ = c.rules[static_cast<uint8_t>(FaultId::ChargeOvercurrent)];
  Rule& ocd = c.rules[static_cast<uint8_t>(FaultId::DischargeOvercurrent)];
  occ.clear = -occ.clear;  // absent while the charge current is below +200 mA
  ocd.clear = -ocd.clear;  // absent while the discharge current is below 200 mA (current above -200 mA)
  return c;
}
inline constexpr ProtectionConfig kSingleOutputLimits = makeSingleOutputLimits(kScanPeriod);
static_assert(kSingleOutputLimits.rules[static_cast<uint8_t>(FaultId::DischargeOvercurrent)].clear == -200 &&
                  kSingleOutputLimits.rules[static_cast<uint8_t>(FaultId::ChargeOvercurrent)].clear == 200,
              "a current fault of a single-output image recovers at zero current");

}  // namespace fw::app
