// The firmware protection limits every image starts from (Li-ion cells), above the monitors' own limits.
//
// Cell voltages and temperatures act on the first scan that shows them: the monitors already filter their
// readings (BQ769x2 per-cell averaging, BQ79616 26 Hz low-pass, BQ4050 gauge filtering), and a second sample
// would add a scan period of latency, past the budget "fault visible -> paths off within one scan period".
// Current waits for two samples (load steps are real but brief); a discharge over-current latches until
// cleared. Stale data and lost communication open both paths.
//
// One constant table (in flash, referenced, never copied) for the 100 ms scan period every image uses.
#pragma once

#include "app/protection.hpp"

namespace fw::app {

inline constexpr Duration kScanPeriod = ms(100);

constexpr ProtectionConfig makeDefaultLimits(Duration scanPeriod) {
  ProtectionConfig c{};
  auto set = [&c](FaultId id, Rule r) { c.rules[static_cast<uint8_t>(id)] = r; };
  set(FaultId::CellOvervoltage, {true, 4250, 4150, 1, {}, false, Action::AllOff});
  set(FaultId::CellUndervoltage, {true, 2700, 2900, 1, {}, false, Action::DischargeOff});
  set(FaultId::ChargeOvercurrent, {true, 20000, 18000, 2, {}, false, Action::ChargeOff});
  set(FaultId::DischargeOvercurrent, {true, -40000, -35000, 2, {}, true, Action::DischargeOff});
  set(FaultId::Overtemperature, {true, 3332, 3282, 1, {}, false, Action::AllOff});      // 60.0 / 55.0 degC
  set(FaultId::Undertemperature, {true, 2532, 2582, 1, {}, false, Action::ChargeOff});  // -20 / -15 degC
  set(FaultId::DeviceSafety, {true, 1, 1, 1, {}, false, Action::AllOff});
  set(FaultId::StaleData, {true, 1, 1, 1, {}, false, Action::AllOff});
  set(FaultId::CommLoss, {true, 1, 1, 1, {}, false, Action::AllOff});
  c.staleAfter = scanPeriod * 3;
  c.commLossScans = 3;
  return c;
}

inline constexpr ProtectionConfig kDefaultLimits = makeDefaultLimits(kScanPeriod);

}  // namespace fw::app
