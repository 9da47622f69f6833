// The MSPM0 operating modes the twin tells apart (SLAU847D/SLAU846B chapter 2 "PMCU", operating modes): the
// core executes (RUN) or waits in WFI or sleep-on-exit. With SCR.SLEEPDEEP clear that is SLEEP; with it set,
// SYSCTL PMODECFG.DSLEEP selects STOP (0) or STANDBY (1) (hw_sysctl PMODECFG_DSLEEP_STOP/STANDBY). STOP's
// sub-mode follows SYSOSCCFG: STOP0 with SYSOSC at its frequency, STOP1 with USE4MHZSTOP (SYSOSC geared to
// 4 MHz), STOP2 with DISABLESTOP (SYSOSC off, ULPCLK from LFCLK); STANDBY0 with MCLKCFG.STOPCLKSTBY clear
// (every PD0 peripheral keeps LFCLK), STANDBY1 with it set (only TIMG0/TIMG1 keep a clock) (mspm0-sdk
// dl_sysctl_mspm0l11xx_l13xx.h DL_SYSCTL_setPowerPolicySTOP0/1/2 and STANDBY0/1 and their comments).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace twin {

enum class PowerMode : uint8_t { Run, Sleep, Stop0, Stop1, Stop2, Standby0, Standby1 };
inline constexpr size_t kPowerModes = 7;

constexpr bool isDeepSleep(PowerMode m) {
  return m >= PowerMode::Stop0;
}
constexpr const char* powerModeName(PowerMode m) {
  constexpr const char* kNames[kPowerModes] = {"RUN",   "SLEEP",    "STOP0",   "STOP1",
                                               "STOP2", "STANDBY0", "STANDBY1"};
  return kNames[static_cast<size_t>(m)];
}

// Cycles spent in each mode over a run (indexed by PowerMode).
using Residency = std::array<uint64_t, kPowerModes>;

}  // namespace twin
