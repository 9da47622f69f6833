// The firmware protection limits every image starts from (Li-ion cells), above the monitors' own limits.
//
// Cell voltages and temperatures act on the first scan that shows them: the monitors already filter their
// readings (BQ769x2 per-cell averaging, BQ79616 26 Hz low-pass, BQ4050 gauge filtering), and a second sample
// would add a scan period of latency, past the budget "fault visible -> paths off within one scan period".
// Current waits for two samples (load steps are real but brief); a discharge over-current latches until
// cleared. Stale data, lost communication and an open sense wire (the cells beside it are unmonitored)
// open both paths.
//
// One constant table (in flash, referenced, never copied) for the 100 ms scan period every image uses.
#pragma once

#include "app/protection/protection.hpp"

namespace fw::app {

inline constexpr Duration kScanPeriod = ms(100);

constexpr Rule limit(int32_t trip, int32_t clear, uint8_t debounce, Action action, bool latch = false) {
  Rule r;
  r.trip = trip, r.clear = clear, r.debounce = debounce, r.action = action, r.latch = latch, r.enabled = true;
  return r;
}

constexpr ProtectionConfig makeDefaultLimits(Duration scanPeriod) {
  ProtectionConfig c{};
  c.rules[static_cast<uint8_t>(FaultId::CellOvervoltage)] = limit(4250, 4150, 1, Action::AllOff);
  c.rules[static_cast<uint8_t>(FaultId::CellUndervoltage)] = limit(2700, 2900, 1, Action::DischargeOff);
  c.rules[static_cast<uint8_t>(FaultId::ChargeOvercurrent)] = limit(20000, 18000, 2, Action::ChargeOff);
  c.rules[static_cast<uint8_t>(FaultId::DischargeOvercurrent)] =
      limit(-40000, -35000, 2, Action::DischargeOff, true);
  c.rules[static_cast<uint8_t>(FaultId::Overtemperature)] =
      limit(3332, 3282, 1, Action::AllOff);  // 60 / 55 degC
  c.rules[static_cast<uint8_t>(FaultId::Undertemperature)] =
      limit(2532, 2582, 1, Action::ChargeOff);  // -20 / -15
  c.rules[static_cast<uint8_t>(FaultId::DeviceSafety)] = limit(1, 1, 1, Action::AllOff);
  c.rules[static_cast<uint8_t>(FaultId::StaleData)] = limit(1, 1, 1, Action::AllOff);
  c.rules[static_cast<uint8_t>(FaultId::CommLoss)] = limit(1, 1, 1, Action::AllOff);
  c.rules[static_cast<uint8_t>(FaultId::OpenWire)] = limit(1, 1, 1, Action::AllOff);
  // An intermittent link: 4 of the last 10 scan attempts failed (a link that fails 40 % of its scans gives
  // no data to trust); clears once 10 attempts in a row validated.
  c.rules[static_cast<uint8_t>(FaultId::CommErrorRate)] = limit(4, 1, 1, Action::AllOff);
  c.rateWindow = 10;
  c.staleAfter = scanPeriod * 3;
  c.commLossScans = 3;
  return c;
}

inline constexpr ProtectionConfig kDefaultLimits = makeDefaultLimits(kScanPeriod);

}  // namespace fw::app
