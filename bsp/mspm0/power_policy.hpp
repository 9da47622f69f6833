// StandbyIdle: fw::hal::PowerPolicy of the MSPM0L1306 images: STANDBY1 between scans, SLEEP0 otherwise.
//
// At each idle (interrupts masked, hal/power.hpp):
// - SLEEP0 (returns false: the scheduler's plain WFI) while the I2C controller runs a transfer (MSR.BUSY) or
//   the UART transmits (STAT.BUSY: a byte in the TX FIFO or the shift register; its DMA refills the FIFO
//   before it drains), whose bit timing needs the 32 MHz BUSCLK that STOP and STANDBY stop (SLAU847D 2 PMCU
//   operating modes), while the earliest deadline is nearer than 2 x kMarginUs (the 1 MHz TimgClock then
//   gives it exactly), and while a falling-edge wake pin (Config::wakePins: ALERT, active low) still reads
//   low: GPIO_ERR_01 case 2 (SLAZ741A 6.4, SLAZ742A): a GPIO pulse still active when the device returns to
//   STANDBY1 after waking it makes the device miss every later wake edge.
// - Otherwise STANDBY1: TimgClock halted, an LFCLK timer (TIMG1, clocked through STANDBY1: SLASEX0D table
//   8-1, SLAU847D 2 "LFCLK") armed for the deadline minus kMarginUs (at most kMaxSleepUs: its 16-bit count
//   wraps in 2 s), SCR.SLEEPDEEP set for this one WFI (the instruction prefetcher is
//   off across it: the scheduler's idle turns it off before asking the policy, fw::port::chipSleepBegin,
//   CPU_ERR_03). After the WFI, interrupts still masked: SLEEPDEEP
//   cleared, the time taken from the LFCLK count (x 1e6 / 32 768 = x 15 625 / 512 us a tick,
//   timeAfterSleep()), TimgClock restarted there and its wake-up re-armed. So no handler ever reads a clock
//   that is behind, and the time is off by less than one LFCLK tick (30.5 us) after a sleep, without adding
//   up (an anchor, not a sum of corrections). What else wakes the core from STANDBY1: the ALERT edge (GPIOA)
//   and a start bit on the UART's RX line, by the asynchronous fast-clock request
//   (dl_sysctl_mspm0l11xx_l13xx.h STANDBY1 doc comment; SLAU847D 2 "LFCLK": "asynchronous fast wake from
//   GPIO, ... or a serial interface"; the twin models this, bsp/twin/README.md "Power").
//
// Contract
// - init(config): thread mode, once, after the clocks (initSysosc): powers the LFCLK timer and starts its
//   free-running count, enables its NVIC line (so that its compare wakes the WFI; it is never taken: the
//   policy clears it before unmasking), and selects STANDBY1 for SCR.SLEEPDEEP (PMODECFG.DSLEEP STANDBY,
//   MCLKCFG.STOPCLKSTBY set), which only this policy sets, for one WFI at a time. LFCLK is the LFOSC, on from
//   reset (SLAU847D 2 "LFOSC").
// - sleep(): hal/power.hpp. The policy owns the LFCLK timer; TimgClock's halt()/resume() its clock.
#pragma once

#include <cstdint>

#include "hal/power.hpp"
#include "timg_clock.hpp"

namespace bsp::mspm0 {

class StandbyIdle final : public fw::hal::PowerPolicy {
 public:
  struct Config {
    uintptr_t lfTimer = 0;  // a TIMG clocked in STANDBY1 (L1306: TIMG1)
    uint8_t lfIrq = 0;
    uintptr_t i2c = 0;       // the I2C controller whose transfers need BUSCLK
    uintptr_t uart = 0;      // the UART whose transmission needs BUSCLK
    uintptr_t wakePort = 0;  // the GPIO port of the falling-edge wake inputs ...
    uint32_t wakePins = 0;   // ... and their DIN bits: STANDBY1 only while all read high (GPIO_ERR_01)
  };

  // What the wake-up needs before the deadline: tWAKE from STANDBY (15 us, SLASEX0D 7.8), one LFCLK tick of
  // rounding (30.5 us), the restart (a few us), with room for the SYSOSC settling after the wake
  // (SYSOSC_ERR_05 allows 10 % slow during asynchronous requests). The remainder is slept in SLEEP0 on the
  // exact clock.
  static constexpr uint32_t kMarginUs = 200;
  // The LFCLK timer counts 16 bits at 32 768 Hz: a sleep ends before the count wraps (2.0 s).
  static constexpr uint32_t kMaxSleepUs = 1875000;
  // The anchor of the time across sleeps (timeAfterSleep) may be this old at a halt: the 1 MHz estimate that
  // resolves the LFCLK counter's wraps is then off by at most 3 % (a SYSOSC far off) x 20 s = 0.6 s, within
  // the half wrap (1 s), and its tick count x 67 fits 32 bits.
  static constexpr uint32_t kMaxAnchorUs = 20000000;
  // From the LFCLK edge the count last took to the read after the wake-up: tWAKE from STANDBY (SLASEX0D
  // 7.8), which is also about half a tick, the average for a wake-up at any other phase.
  static constexpr uint32_t kWakeUs = 15;

  constexpr StandbyIdle(TimgClock& clock, const Config& config) : clock_(clock), config_(config) {}

  static void init(const Config& config);

  // A TimgClock time and the LFCLK count (16 bits) of the same instant.
  struct Anchor {
    uint32_t us = 0;
    uint32_t lf = 0;
  };
  // The time after a sleep: the clock stopped at `halted` with the LFCLK count at `lfAtHalt` and reads
  // `lfNow` after the wake-up; moves `anchor` on (power_policy.cpp; exposed for tests).
  static fw::Instant timeAfterSleep(Anchor& anchor, fw::Instant halted, uint32_t lfAtHalt, uint32_t lfNow);

 private:
  bool doSleep(bool timed, fw::Instant deadline) override;

  TimgClock& clock_;
  Config config_;
  Anchor anchor_{};  // (0, 0): TIMG1 starts from zero right after TimgClock, in bringUp()
};

}  // namespace bsp::mspm0
