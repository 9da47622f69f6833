// Register-level tests of the TIMG scheduler clock (bsp/mspm0/timg_clock.*) on the twin's TIMG0
// (bsp/twin/periph/timg.hpp: a 16-bit counter on BUSCLK / (CPS.PCNT + 1), LOAD/ZERO/CCUn events exact to the
// timer clock). Time passes on the twin; the test takes the timer's interrupt when the twin's MIS shows one,
// as the core would. Addresses: TIMG0_BASE 0x40084000 + GPTIMER.* offsets (mspm0l1306.tsv); CC/CCCTL at
// 0x1810/0x1830 and the CCU0/CCU1 bits (8/9) from the TIMx register description (SLAU846A section 23,
// mspm0-data tim_v1.yaml).
#include <gtest/gtest.h>

#include <cstdint>

#include "fixture.hpp"
#include "timg_clock.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kBase = 0x40084000;
constexpr uintptr_t kImask = kBase + 0x1028;
constexpr uintptr_t kMis = kBase + 0x1038;
constexpr uintptr_t kIset = kBase + 0x1040;
constexpr uintptr_t kIclr = kBase + 0x1048;
constexpr uintptr_t kCps = kBase + 0x110C;
constexpr uintptr_t kCtrctl = kBase + 0x1804;
constexpr uintptr_t kLoad = kBase + 0x1808;
constexpr uintptr_t kCc0 = kBase + 0x1810;
constexpr uintptr_t kCc1 = kBase + 0x1814;
constexpr uint32_t kLoadEvent = 1U << 1;  // GPTIMER_CPU_INT_IMASK_L
constexpr uint32_t kCcu0 = 1U << 8;
constexpr uint32_t kCcu1 = 1U << 9;
constexpr uint64_t kCyclesPerUs = 32;  // the counter's tick: BUSCLK 32 MHz / (PCNT 31 + 1)

class ClockTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    startClock(clock);
  }
  // Starts `timgClock` and notes the cycle of its CTRCTL enable: tick n of the counter comes 32 n cycles
  // later (the hook runs after the write's 2 cycles, mmio_model.hpp).
  void startClock(TimgClock& timgClock) {
    regs().onWrite(kCtrctl, [this](uint32_t v) {
      if (v & 1U) started_ = chip().machine().now() - 2;
    });
    timgClock.start();
  }
  // Microseconds the counter has counted since the start.
  uint64_t elapsedUs() { return (chip().machine().now() - started_) / kCyclesPerUs; }
  // Lets time pass to the start of the counter's tick `us` (the reads that follow stay within it).
  void runTo(uint64_t us) {
    const uint64_t target = started_ + us * kCyclesPerUs;
    ASSERT_LE(chip().machine().now(), target);
    regs().advance(target - chip().machine().now());
  }
  // The core takes the timer's interrupt if the twin's MIS shows one.
  bool takeInterrupt(TimgClock& timgClock) {
    if (regs().peek(kMis) == 0) return false;
    timgClock.onInterrupt();
    return true;
  }
  // Lets time pass to tick `us` (or a few cycles past it, for an interrupt due on it), taking each interrupt
  // as it comes.
  void runServicingTo(uint64_t us) {
    const uint64_t target = started_ + us * kCyclesPerUs;
    while (regs().runUntilEvent([this] { return regs().peek(kMis) != 0; },
                                (target - chip().machine().now()) / kCyclesPerUs))
      clock.onInterrupt();
    if (chip().machine().now() < target) regs().advance(target - chip().machine().now());
  }

  TimgClock clock{{kBase, 16, 31}};
  uint64_t started_ = 0;
};

TEST_F(ClockTest, StartCounts1MHzUpWithTwoEventsPerWrap) {
  EXPECT_EQ(regs().lastWrite(kCps), 31U);  // 32 MHz / (31 + 1) = 1 MHz (PCNT: divide by PCNT + 1)
  EXPECT_EQ(regs().lastWrite(kLoad), 0xFFFFU);
  EXPECT_EQ(regs().lastWrite(kCc1), 0x8000U);
  EXPECT_EQ(regs().lastWrite(kImask), kLoadEvent | kCcu1);
  // CTRCTL: EN | REPEAT 1 | CM up (2 << 4) | CVAE zero (2 << 28); CLC/CAC/CZC 0.
  EXPECT_EQ(regs().lastWrite(kCtrctl), 0x1U | 0x2U | 0x20U | 0x20000000U);
  EXPECT_EQ(regs().lastWrite(0xE000E100), 1U << 16);  // TIMG0 is IRQ 16
}

TEST_F(ClockTest, WidensThe16BitCounterAcrossWraps) {
  runTo(0x0010);
  EXPECT_EQ(clock.now().us, 0x10U);
  runTo(0x7FF0);
  EXPECT_EQ(clock.now().us, 0x7FF0U);
  runTo(0x8004);
  ASSERT_EQ(regs().peek(kMis), kCcu1);
  EXPECT_EQ(clock.now().us, 0x8004U);  // half event pending, not yet counted
  ASSERT_TRUE(takeInterrupt(clock));
  EXPECT_EQ(regs().lastWrite(kIclr), kCcu1);
  runTo(0x8010);
  EXPECT_EQ(clock.now().us, 0x8010U);
  runTo(0x10003);
  ASSERT_EQ(regs().peek(kMis), kLoadEvent);
  EXPECT_EQ(clock.now().us, 0x10003U);  // wrapped, load event still pending
  ASSERT_TRUE(takeInterrupt(clock));
  runTo(0x10005);
  EXPECT_EQ(clock.now().us, 0x10005U);
  runServicingTo(0x20001);
  EXPECT_EQ(clock.now().us, 0x20001U);
}

TEST_F(ClockTest, AnEventTakenOneTickEarlyDoesNotJumpAhead) {
  // LOAD is set as the counter becomes 0xFFFF (hw_gptimer.h CPU_INT L): an interrupt taken at once finds the
  // counter still in the first half.
  runServicingTo(0xFFFE);
  ASSERT_TRUE(regs().runUntilEvent([this] { return regs().peek(kMis) != 0; }, 2));
  ASSERT_TRUE(takeInterrupt(clock));
  EXPECT_EQ(clock.now().us, 0xFFFFU);
  runTo(0x10000);
  EXPECT_EQ(clock.now().us, 0x10000U);
}

TEST_F(ClockTest, WidenIsMonotonicOverManyPeriods) {
  uint32_t halves = 0;
  uint32_t previous = 0;
  for (uint32_t t = 0; t < 6 * 0x10000; t += 0x1234) {
    const uint32_t counter = t & 0xFFFF;
    // The interrupt is serviced with some latency: count the halves crossed 0x100 ticks ago.
    const uint32_t serviced = t < 0x100 ? 0 : (t - 0x100) >> 15;
    halves = serviced;
    const uint32_t now = TimgClock::widen(halves, counter);
    EXPECT_EQ(now, t);
    EXPECT_GE(now, previous);
    previous = now;
  }
}

TEST_F(ClockTest, WakeAtArmsTheCompareForNearDeadlines) {
  runTo(100);
  regs().clearLog();
  clock.wakeAt(fw::Instant{600});
  EXPECT_EQ(regs().lastWrite(kCc0), 600U);
  EXPECT_EQ(regs().lastWrite(kIclr), kCcu0);
  EXPECT_NE(regs().lastWrite(kImask).value() & kCcu0, 0U);
  EXPECT_FALSE(regs().lastWrite(kIset).has_value());
  ASSERT_TRUE(regs().runUntilEvent([this] { return regs().peek(kMis) != 0; }, 1000));
  EXPECT_EQ(elapsedUs(), 600U) << "CCU0 as the counter becomes CC0";
  ASSERT_TRUE(takeInterrupt(clock));  // one-shot: the alarm disarms itself
  EXPECT_EQ(regs().lastWrite(kImask).value() & kCcu0, 0U);
}

TEST_F(ClockTest, WakeAtPendsTheInterruptWhenTheDeadlinePassedWhileArming) {
  // The counter passes CC0 = 600 right after CC0 is written (time the core spends elsewhere, here let pass on
  // the twin): the compare fires, the arming's ICLR wipes it, and only the re-check's ISET keeps the wake-up.
  runTo(100);
  regs().onWrite(kCc0, [this](uint32_t) { regs().advanceUs(600); });
  regs().clearLog();
  clock.wakeAt(fw::Instant{600});
  EXPECT_EQ(regs().lastWrite(kIset), kCcu0);
  EXPECT_EQ(regs().peek(kMis), kCcu0);
}

TEST_F(ClockTest, FarDeadlinesArmAnIntermediateWakeUpLessThanAWrapAhead) {
  runTo(100);
  regs().clearLog();
  clock.wakeAt(fw::Instant{100 + 100000});  // beyond one wrap of the 16-bit counter (65 536 us)
  ASSERT_TRUE(regs().lastWrite(kCc0).has_value());
  const uint32_t cc0 = regs().lastWrite(kCc0).value();
  // Armed ahead of the counter by less than a wrap (so it cannot alias) and by more than half a wrap (so the
  // steps are few); the deadline itself is armed from a later wakeAt().
  const uint32_t ahead = (cc0 - 100) & 0xFFFF;
  EXPECT_GT(ahead, 0x8000U);
  EXPECT_LT(ahead, 0xFFFFU - 0x100U);
  EXPECT_NE(regs().lastWrite(kImask).value() & kCcu0, 0U);
  EXPECT_FALSE(regs().lastWrite(kIset).has_value());
}

TEST_F(ClockTest, WakeArmedFromWakeAtUntilTheAlarmFires) {
  // The scheduler leaves the clock unread while this says true (firmware/hal/clock.hpp): it must turn false
  // exactly when the handler took the alarm, and never be true with no alarm armed.
  EXPECT_FALSE(clock.wakeArmed()) << "nothing armed yet";
  runTo(100);
  clock.wakeAt(fw::Instant{600});
  EXPECT_TRUE(clock.wakeArmed());
  runServicingTo(599);  // nothing fires before CC0
  EXPECT_TRUE(clock.wakeArmed());
  ASSERT_TRUE(regs().runUntilEvent([this] { return regs().peek(kMis) != 0; }, 2));
  ASSERT_TRUE(takeInterrupt(clock));
  EXPECT_FALSE(clock.wakeArmed());
  // A half-period count is not the alarm.
  clock.wakeAt(fw::Instant{0x8000 + 100});
  runServicingTo(0x8000 + 50);
  EXPECT_TRUE(clock.wakeArmed()) << "CCU1 at 0x8000 taken, the alarm still armed";
  // A far deadline: its intermediate wake-up counts as the armed one, and fires before the deadline.
  runServicingTo(0x8000 + 100);
  EXPECT_FALSE(clock.wakeArmed());
  const uint64_t from = elapsedUs();
  clock.wakeAt(fw::Instant{static_cast<uint32_t>(from) + 100000});
  EXPECT_TRUE(clock.wakeArmed());
  ASSERT_TRUE(regs().runUntilEvent([this] { return (regs().peek(kMis) & kCcu0) != 0; }, 100000));
  EXPECT_LT(elapsedUs(), from + 100000);
  ASSERT_TRUE(takeInterrupt(clock));
  EXPECT_FALSE(clock.wakeArmed());
}

// The clock driven the way the scheduler's idle loop drives it: check the deadline, wakeAt(), sleep until an
// interrupt, take it, check again.
class ClockWakeTest : public ClockTest {
 protected:
  // The microsecond (since the start) at which the idle loop sees `deadline` due.
  uint64_t sleepUntil(TimgClock& timgClock, uint32_t deadline) {
    for (int wakeUps = 0; wakeUps < 64; ++wakeUps) {
      if (fw::isDue(fw::Instant{deadline}, timgClock.now())) return elapsedUs();
      timgClock.wakeAt(fw::Instant{deadline});
      if (!regs().runUntilEvent([this] { return regs().peek(kMis) != 0; }, 0x20000)) break;
      timgClock.onInterrupt();
    }
    ADD_FAILURE() << "no wake-up for " << deadline;
    return 0;
  }
};

TEST_F(ClockWakeTest, WakesOnTheDeadlineTickAtAnyDistanceAndPhase) {
  // Distances around the old 16 384 us limit, the half period, a wrap and several wraps, from starting points
  // all over the counter's range (just before each half-period event, just after it, in between).
  constexpr uint32_t kDistances[] = {1,     700,   16383, 16385, 20000,  32000, 32769,
                                     40000, 65535, 65537, 70000, 100000, 250000};
  constexpr uint32_t kStarts[] = {100, 0x3FFF, 0x7F00, 0x8010, 0xC000, 0xFF80, 0x10005};
  for (uint32_t start : kStarts) {
    for (uint32_t distance : kDistances) {
      SCOPED_TRACE(::testing::Message() << "start " << start << " us, deadline " << distance << " us later");
      RegisterTest::SetUp();
      TimgClock fresh{{kBase, 16, 31}};
      startClock(fresh);
      ASSERT_EQ(sleepUntil(fresh, start), start);
      const uint32_t deadline = start + distance;
      // Exact: CCU0 is set on the tick the counter becomes CC0 (1 us at 1 MHz), and the idle loop sees the
      // deadline due in that interrupt. Before the fix a deadline more than 16 384 us away woke at the next
      // half-period event instead, up to 16.4 ms late.
      EXPECT_EQ(sleepUntil(fresh, deadline), deadline);
    }
  }
}

TEST_F(ClockWakeTest, WakeUpsForOtherInterruptsLeaveTheDeadlineExact) {
  // The scheduler's idle loop, woken by other interrupts (the bytes of an I2C scan, every 997 us here), reads
  // the clock and re-arms only once the armed wake-up has fired (wakeArmed() false): the deadline is still
  // seen on its own tick, at any distance (a far one through its intermediate wake-ups).
  for (uint32_t distance : {700U, 20000U, 65535U, 70000U, 250000U}) {
    SCOPED_TRACE(::testing::Message() << "deadline " << distance << " us ahead");
    RegisterTest::SetUp();
    TimgClock fresh{{kBase, 16, 31}};
    startClock(fresh);
    ASSERT_EQ(sleepUntil(fresh, 100), 100U);
    const uint32_t deadline = 100 + distance;
    uint64_t seen = 0;
    for (int wakeUps = 0; wakeUps < 2000 && seen == 0; ++wakeUps) {
      if (!fresh.wakeArmed()) {
        if (fw::isDue(fw::Instant{deadline}, fresh.now())) {
          seen = elapsedUs();
          break;
        }
        fresh.wakeAt(fw::Instant{deadline});
      }
      // The timer's interrupt, else another peripheral's 997 us on.
      if (regs().runUntilEvent([this] { return regs().peek(kMis) != 0; }, 997)) fresh.onInterrupt();
    }
    EXPECT_EQ(seen, deadline);
  }
}

}  // namespace
}  // namespace bsp::mspm0::test
