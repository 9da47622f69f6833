// Register-level tests of the TIMG scheduler clock (bsp/mspm0/timg_clock.*). Addresses: TIMG0_BASE
// 0x40084000 + GPTIMER.* offsets (mspm0l1306.tsv); CC/CCCTL at 0x1810/0x1830 and the CCU0/CCU1 bits (8/9)
// from the TIMx register description (SLAU846A section 23, mspm0-data tim_v1.yaml).
#include <gtest/gtest.h>

#include <cstdint>

#include "fixture.hpp"
#include "timg_clock.hpp"
#include "timg_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kBase = 0x40084000;
constexpr uintptr_t kImask = kBase + 0x1028;
constexpr uintptr_t kMis = kBase + 0x1038;
constexpr uintptr_t kIset = kBase + 0x1040;
constexpr uintptr_t kIclr = kBase + 0x1048;
constexpr uintptr_t kCps = kBase + 0x110C;
constexpr uintptr_t kCtr = kBase + 0x1800;
constexpr uintptr_t kCtrctl = kBase + 0x1804;
constexpr uintptr_t kLoad = kBase + 0x1808;
constexpr uintptr_t kCc0 = kBase + 0x1810;
constexpr uintptr_t kCc1 = kBase + 0x1814;
constexpr uint32_t kLoadEvent = 1U << 1;  // GPTIMER_CPU_INT_IMASK_L
constexpr uint32_t kCcu0 = 1U << 8;
constexpr uint32_t kCcu1 = 1U << 9;

class ClockTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    clock.start();
  }
  void interrupt(uint32_t pending) {
    regs().queueRead(kMis, pending);
    clock.onInterrupt();
  }
  uint32_t nowAt(uint32_t counter) {
    regs().queueRead(kCtr, counter);
    return clock.now().us;
  }

  TimgClock clock{{kBase, 16, 31}};
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
  EXPECT_EQ(nowAt(0x0010), 0x10U);
  EXPECT_EQ(nowAt(0x7FF0), 0x7FF0U);
  EXPECT_EQ(nowAt(0x8004), 0x8004U);  // half event pending, not yet counted
  interrupt(kCcu1);
  EXPECT_EQ(regs().lastWrite(kIclr), kCcu1);
  EXPECT_EQ(nowAt(0x8010), 0x8010U);
  EXPECT_EQ(nowAt(0x0003), 0x10003U);  // wrapped, load event still pending
  interrupt(kLoadEvent);
  EXPECT_EQ(nowAt(0x0005), 0x10005U);
  interrupt(kCcu1);
  interrupt(kLoadEvent);
  EXPECT_EQ(nowAt(0x0001), 0x20001U);
}

TEST_F(ClockTest, AnEventTakenOneTickEarlyDoesNotJumpAhead) {
  interrupt(kCcu1);
  interrupt(kLoadEvent);  // taken while the counter still reads 0xFFFF
  EXPECT_EQ(nowAt(0xFFFF), 0xFFFFU);
  EXPECT_EQ(nowAt(0x0000), 0x10000U);
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
  regs().clearLog();
  regs().queueReads(kCtr, {100, 110});
  clock.wakeAt(fw::Instant{600});
  EXPECT_EQ(regs().lastWrite(kCc0), 600U);
  EXPECT_EQ(regs().lastWrite(kIclr), kCcu0);
  EXPECT_NE(regs().lastWrite(kImask).value() & kCcu0, 0U);
  EXPECT_FALSE(regs().lastWrite(kIset).has_value());
  interrupt(kCcu0);  // one-shot: the alarm disarms itself
  EXPECT_EQ(regs().lastWrite(kImask).value() & kCcu0, 0U);
}

TEST_F(ClockTest, WakeAtPendsTheInterruptWhenTheDeadlinePassedWhileArming) {
  regs().clearLog();
  regs().queueReads(kCtr, {100, 700});  // the counter passed CC0 = 600 between the two reads
  clock.wakeAt(fw::Instant{600});
  EXPECT_EQ(regs().lastWrite(kIset), kCcu0);
}

TEST_F(ClockTest, FarDeadlinesArmAnIntermediateWakeUpLessThanAWrapAhead) {
  regs().clearLog();
  regs().queueReads(kCtr, {100, 110});
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
  regs().queueReads(kCtr, {100, 110});
  clock.wakeAt(fw::Instant{600});
  EXPECT_TRUE(clock.wakeArmed());
  interrupt(kLoadEvent);  // a half-period count is not the alarm
  EXPECT_TRUE(clock.wakeArmed());
  interrupt(kCcu0);
  EXPECT_FALSE(clock.wakeArmed());
  // A far deadline: its intermediate wake-up counts as the armed one, and fires before the deadline.
  regs().queueReads(kCtr, {120, 125});
  clock.wakeAt(fw::Instant{120 + 100000});
  EXPECT_TRUE(clock.wakeArmed());
  interrupt(kCcu0);
  EXPECT_FALSE(clock.wakeArmed());
}

// The clock against a counting timer (timg_model.hpp), driven the way the scheduler's idle loop drives it:
// check the deadline, wakeAt(), sleep until an interrupt, take it, check again.
class ClockWakeTest : public ClockTest {
 protected:
  void SetUp() override {
    ClockTest::SetUp();
    timer.attach();
  }
  // The timer tick at which the idle loop sees `deadline` due.
  uint64_t sleepUntil(TimgClock& timgClock, uint32_t deadline) {
    for (int wakeUps = 0; wakeUps < 64; ++wakeUps) {
      if (fw::isDue(fw::Instant{deadline}, timgClock.now())) return timer.now();
      timgClock.wakeAt(fw::Instant{deadline});
      if (!timer.runUntilInterrupt(0x20000)) break;
      timgClock.onInterrupt();
    }
    ADD_FAILURE() << "no wake-up for " << deadline;
    return 0;
  }
  TimgModel timer{kBase};
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
      fresh.start();
      timer.attach();
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
  // The scheduler's idle loop, woken by other interrupts (the bytes of an I2C scan), reads the clock and
  // re-arms only once the armed wake-up has fired (wakeArmed() false): the deadline is still seen on its own
  // tick, at any distance (a far one through its intermediate wake-ups).
  for (uint32_t distance : {700U, 20000U, 65535U, 70000U, 250000U}) {
    SCOPED_TRACE(::testing::Message() << "deadline " << distance << " us ahead");
    RegisterTest::SetUp();
    TimgClock fresh{{kBase, 16, 31}};
    fresh.start();
    timer.attach();
    ASSERT_EQ(sleepUntil(fresh, 100), 100U);
    const uint32_t deadline = 100 + distance;
    uint64_t seen = 0;
    for (int wakeUps = 0; wakeUps < 2000 && seen == 0; ++wakeUps) {
      if (!fresh.wakeArmed()) {
        if (fw::isDue(fw::Instant{deadline}, fresh.now())) {
          seen = timer.now();
          break;
        }
        fresh.wakeAt(fw::Instant{deadline});
      }
      if (timer.runUntilInterrupt(997)) fresh.onInterrupt();  // else another peripheral's interrupt woke it
    }
    EXPECT_EQ(seen, deadline);
  }
}

}  // namespace
}  // namespace bsp::mspm0::test
