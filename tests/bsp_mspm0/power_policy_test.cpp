// StandbyIdle's time across STANDBY (bsp/mspm0/power_policy.hpp timeAfterSleep): the 1 MHz clock is halted
// for each deep sleep and restarted at a time taken from the LFCLK count (32 768 Hz, a 16-bit counter). Real
// time here runs in nanoseconds; LFCLK edge n comes at n x 1e9 / 32 768 ns; the 1 MHz clock counts whole
// microseconds from where it was restarted; the read after the wake-up comes tWAKE (15 us, SLASEX0D 7.8)
// after the edge that ends the sleep, as when TIMG1's compare wakes the core.
#include <gtest/gtest.h>

#include <cstdint>

#include "fixture.hpp"
#include "gpio.hpp"
#include "hal/irq.hpp"
#include "power_policy.hpp"
#include "timg_clock.hpp"

namespace {

using bsp::mspm0::StandbyIdle;
using bsp::mspm0::TimgClock;

constexpr uint64_t kNsPerSecond = 1000000000;
constexpr uint64_t kWakeNs = 15000;

uint64_t lfEdgesAt(uint64_t ns) {
  return ns * 32768 / kNsPerSecond;
}
uint64_t nsOfEdge(uint64_t edge) {
  return (edge * kNsPerSecond + 32767) / 32768;
}

// Runs `sleeps` cycles of awake `awakeNs` then asleep until the first LFCLK edge `sleepNs` later, and returns
// the worst |1 MHz clock - real time| in ns seen at any wake; `lastOffsetNs` is the final one (signed).
struct SleepRun {
  int64_t worstNs = 0;
  int64_t lastOffsetNs = 0;
  bool monotonic = true;
};
SleepRun runSleeps(int sleeps, uint64_t awakeNs, uint64_t sleepNs) {
  StandbyIdle::Anchor anchor;
  uint64_t realNs = 3000;    // TIMG1 starts 3 us after TimgClock (bringUp())
  uint64_t clockBaseNs = 0;  // real time at which the 1 MHz clock was (re)started ...
  uint32_t clockBaseUs = 3;  // ... at this value
  uint32_t lastUs = 0;
  SleepRun run;
  for (int i = 0; i < sleeps; ++i) {
    realNs += awakeNs;
    const fw::Instant halted{clockBaseUs + static_cast<uint32_t>((realNs - clockBaseNs) / 1000)};
    const uint32_t lfAtHalt = static_cast<uint32_t>(lfEdgesAt(realNs)) & 0xFFFF;
    const uint64_t wakeEdge = lfEdgesAt(realNs + sleepNs) + 1;
    realNs = nsOfEdge(wakeEdge) + kWakeNs;
    const uint32_t lfNow = static_cast<uint32_t>(lfEdgesAt(realNs)) & 0xFFFF;
    const fw::Instant now = StandbyIdle::timeAfterSleep(anchor, halted, lfAtHalt, lfNow);
    if (fw::isBefore(now, halted) || fw::isBefore(now, fw::Instant{lastUs})) run.monotonic = false;
    lastUs = now.us;
    clockBaseNs = realNs;
    clockBaseUs = now.us;
    const int64_t offset = static_cast<int64_t>(uint64_t{now.us} * 1000) - static_cast<int64_t>(realNs);
    run.lastOffsetNs = offset;
    if (offset > run.worstNs || -offset > run.worstNs) run.worstNs = offset < 0 ? -offset : offset;
  }
  return run;
}

TEST(StandbyTime, ScansAtAFixedPhaseDoNotDrift) {
  // The image's pattern: awake a fixed time after each wake, then asleep to the next scan. The halt then
  // falls at the same phase of the LFCLK tick every time; a sum of truncated corrections lost the same
  // fraction each sleep (61 us/s on the twin). 10 000 sleeps (1 000 s): the 32-bit microsecond clock, the
  // 16-bit LFCLK counter and the anchor's steps all wrap or move many times.
  const SleepRun run = runSleeps(10000, 2300000, 97700000);
  EXPECT_TRUE(run.monotonic);
  EXPECT_LT(run.worstNs, 31000) << "within one LFCLK tick at every wake";
  EXPECT_LT(run.lastOffsetNs < 0 ? -run.lastOffsetNs : run.lastOffsetNs, 31000) << "no drift after 1 000 s";
}

TEST(StandbyTime, LongestSleepsAcrossTheCounterWrapStayExact) {
  // Sleeps of 1.875 s (kMaxSleepUs), the LFCLK counter wrapping every 2 s.
  const SleepRun run = runSleeps(500, 100000000, StandbyIdle::kMaxSleepUs * 1000ULL);
  EXPECT_TRUE(run.monotonic);
  EXPECT_LT(run.worstNs, 31000);
}

TEST(StandbyTime, LongAwakeSpellsKeepTheAnchor) {
  // Awake 7 s between sleeps (the bus busy that long): the anchor is moved on at each halt, so the time stays
  // within a tick.
  const SleepRun run = runSleeps(50, 7000000000ULL, 50000000);
  EXPECT_TRUE(run.monotonic);
  EXPECT_LT(run.worstNs, 31000);
}

TEST(StandbyTime, AnAnchorOlderThanItsLimitIsReplacedAtATickAtMost) {
  // Awake 25 s, longer than kMaxAnchorUs: each such sleep starts a new anchor and may err by a tick.
  constexpr int kSleeps = 10;
  const SleepRun run = runSleeps(kSleeps, 25000000000ULL, 50000000);
  EXPECT_TRUE(run.monotonic);
  EXPECT_LT(run.worstNs, kSleeps * 31000);
}

TEST(StandbyTime, NeverStepsBackBehindTheHaltedTime) {
  // A wake-up read right after the halt (the WFI returned at once: an interrupt already pending), the count
  // one edge on from the anchor: the time computed from the count lies before the halted time (the 1 MHz
  // clock ran ahead of the anchor's tick), and the halted time is kept.
  StandbyIdle::Anchor anchor{1000, 0};
  const fw::Instant halted{1000 + 50};  // 1.6 ticks after the anchor: the count says 1 tick + tWAKE, 45 us
  const fw::Instant now = StandbyIdle::timeAfterSleep(anchor, halted, 1, 1);
  EXPECT_EQ(now.us, halted.us);
}

// doSleep on the register model and an L1306 twin (mspm0l130x.h addresses): TIMG0 the 1 MHz clock, TIMG1 on
// LFCLK (IRQ 2), I2C0 and UART0 powered as the board's bring-up powers them, ALERT on PA15 (PINCM16) an
// edge input with its pull-up, driven low from outside the chip by its device, SCR at 0xE000ED10 (ARMv6-M
// ARM B3.2.7). The prefetcher off across the sleep (CPU_ERR_03) is the scheduler's, around this policy
// (tests/sched/idle_test.cpp; on the images the twin's PREFETCH-SLEEP rule).
constexpr uintptr_t kScr = 0xE000ED10;
constexpr bsp::mspm0::Pin kAlertPin{0, 15, 16};
constexpr uintptr_t kI2c0 = 0x400F0000, kUart0 = 0x40108000, kGpioa = 0x400A0000;

class StandbyIdleTest : public bsp::mspm0::test::RegisterTest {
 protected:
  StandbyIdleTest() : RegisterTest(twin::Part::L1306) {}
  void SetUp() override {
    RegisterTest::SetUp();
    bsp::mspm0::powerGpioPort(kGpioa);
    clock.start();
    StandbyIdle::init(kConfig);
    bsp::mspm0::reg::resetAndPowerUp(bsp::mspm0::reg::gprcm(kI2c0));
    bsp::mspm0::reg::resetAndPowerUp(bsp::mspm0::reg::gprcm(kUart0));
    alert.init();
    regs().clearLog();
  }
  // The scheduler's idle: interrupts masked, nothing due (untimed).
  bool idle() {
    const uint32_t saved = fw::port::irqSave();
    const bool slept = idle_.sleep(false, fw::Instant{});
    fw::port::irqRestore(saved);
    return slept;
  }
  // The BQ76952 holds ALERT low (asserted) or releases it (the pull-up makes the high).
  void alertHeldLow(bool low) {
    chip().pins().setExternal(kAlertPin.pincm, low ? twin::Drive::Low : twin::Drive::None);
  }

  static constexpr StandbyIdle::Config kConfig{0x40086000, 2, kI2c0, kUart0, kGpioa, kAlertPin.mask()};
  TimgClock clock{{0x40084000, 16, 31}};
  StandbyIdle idle_{clock, kConfig};
  bsp::mspm0::GpioEdgeInput alert{kAlertPin, bsp::mspm0::Edge::Falling, bsp::mspm0::Pull::Up};
};

TEST_F(StandbyIdleTest, AWakePinStillLowKeepsTheCoreOutOfStandby) {
  // GPIO_ERR_01 case 2: back in STANDBY1 with the wake pulse still active, no later wake edge is detected.
  // ALERT (falling edge, active low) still low: SLEEP0 (false, SCR untouched); high again: STANDBY1.
  alertHeldLow(true);
  EXPECT_FALSE(idle());
  EXPECT_TRUE(regs().writes(kScr).empty());
  alertHeldLow(false);
  EXPECT_TRUE(idle());
  EXPECT_FALSE(regs().writes(kScr).empty());
}

}  // namespace
