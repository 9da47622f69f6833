// WindowWatchdog: fw::hal::Watchdog on the MSPM0 window watchdog (WWDT0), plus the stack-overflow guard.
//
// The WWDT counts LFCLK (32 768 Hz, always running) and resets the device unless restarted in time. A WWDT0
// violation is a BOOTRST ("A WWDT0 violation generates a BOOTRST", SLAU846B / SLAU847D WWDT overview): SRAM
// is reset with everything else, so no fault record survives it; the next boot sees only RSTCAUSE 0x0E
// "WWDT0 violation" (fault.hpp takeStartupReport, published in the Startup message). start() selects 2^15
// counts at /1: a 1.0 s timeout, with no closed window (WINDOW0 = 0 %), so the scheduler may feed it at any
// point of the period; the scheduler's supervision window (250 ms in the images) is the real check that
// every task makes progress.
//
// Contract
// - start(): thread mode, once. The WWDT cannot be stopped afterwards (by design of the hardware).
// - feed(): task context (the scheduler's supervisor). First checks the stack guard words at the bottom of
//   the stack reservation (painted by the reset handler); if one was overwritten the stack has overflowed
//   into other data, and feed() calls fw::onFault(Module::Bsp, line) instead of feeding (a software SYSRST
//   that keeps its record): a cheap run-time guard on a core without an MPU. Then restarts the counter.
#pragma once

#include <cstdint>

#include "hal/watchdog.hpp"

namespace bsp::mspm0 {

inline constexpr uint32_t kStackGuardWords = 2;
inline constexpr uint32_t kStackGuardPattern = 0x5AFE57AC;

class WindowWatchdog final : public fw::hal::Watchdog {
 public:
  // `guard` points at the kStackGuardWords guard words (nullptr: no guard check).
  constexpr WindowWatchdog(uintptr_t base, const volatile uint32_t* guard) : base_(base), guard_(guard) {}
  void start();
  // feed()'s check of the stack guard word (tests call it too).
  bool stackGuardIntact() const {
    if (guard_ == nullptr) return true;
    for (uint32_t i = 0; i < kStackGuardWords; ++i) {
      if (guard_[i] != kStackGuardPattern) return false;
    }
    return true;
  }

 private:
  void doFeed() override;

  uintptr_t base_;
  const volatile uint32_t* guard_;
};

}  // namespace bsp::mspm0
