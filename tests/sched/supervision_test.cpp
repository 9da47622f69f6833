// Run-time budgets, overrun detection and watchdog supervision.
#include <gtest/gtest.h>

#include "fn_task.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"

namespace {

using fw::ms;
using fw::us;
using fw::sched::TraceKind;
using test::FnTask;

TEST(SchedSupervision, RunLongerThanBudgetIsAnOverrun) {
  bsp::host::Harness h;
  FnTask task;
  task.set([&](fw::sched::EventMask) { h.clock.advance(ms(3)); });
  h.sched.addTask(2, task, ms(1));
  h.sched.post(2, 0x1);
  h.runUntilIdle();
  EXPECT_EQ(h.sched.stats(2).overruns, 1u);
  EXPECT_EQ(h.sched.stats(2).worstRun, ms(3));
  EXPECT_EQ(h.trace.count(TraceKind::Overrun, 2), 1u);
}

TEST(SchedSupervision, WorstRunTimeIsTheMaximumAndWithinBudgetIsNoOverrun) {
  bsp::host::Harness h;
  FnTask task;
  const uint32_t costs[] = {200, 900, 350, 1000, 10};
  size_t i = 0;
  task.set([&](fw::sched::EventMask) { h.clock.advance(us(costs[i++])); });
  h.sched.addTask(1, task, ms(1));
  for (size_t k = 0; k < 5; ++k) {
    h.sched.post(1, 0x1);
    h.runUntilIdle();
  }
  EXPECT_EQ(h.sched.stats(1).runs, 5u);
  EXPECT_EQ(h.sched.stats(1).worstRun, us(1000));
  EXPECT_EQ(h.sched.stats(1).overruns, 0u) << "exactly the budget is allowed";
}

TEST(SchedSupervision, WatchdogFedWhileEveryWatchedTaskChecksIn) {
  bsp::host::Harness h;
  bsp::host::SimWatchdog wdt(h.clock);
  FnTask a, b;
  a.set([&](fw::sched::EventMask) { h.sched.checkIn(1); });
  b.set([&](fw::sched::EventMask) { h.sched.checkIn(2); });
  h.sched.addTask(1, a, {}, true);
  h.sched.addTask(2, b, {}, true);
  fw::sched::Timer ta, tb;
  h.sched.startTimer(ta, 1, 0x1, ms(10), ms(10));
  h.sched.startTimer(tb, 2, 0x1, ms(25), ms(25));
  h.sched.superviseWatchdog(wdt, ms(50));
  h.runFor(ms(1000));
  EXPECT_EQ(wdt.feeds().size(), 20u);
  EXPECT_EQ(h.trace.count(TraceKind::WatchdogStarved), 0u);
  EXPECT_LE(wdt.longestGapUs(0), 50000u);
}

TEST(SchedSupervision, WatchdogNotFedWhenOneTaskStalls) {
  bsp::host::Harness h;
  bsp::host::SimWatchdog wdt(h.clock);
  FnTask a, b;
  bool bStalled = false;
  a.set([&](fw::sched::EventMask) { h.sched.checkIn(1); });
  b.set([&](fw::sched::EventMask) {
    if (!bStalled) h.sched.checkIn(2);  // a stuck state machine: runs, but never completes its work
  });
  h.sched.addTask(1, a, {}, true);
  h.sched.addTask(2, b, {}, true);
  fw::sched::Timer ta, tb;
  h.sched.startTimer(ta, 1, 0x1, ms(10), ms(10));
  h.sched.startTimer(tb, 2, 0x1, ms(10), ms(10));
  h.sched.superviseWatchdog(wdt, ms(50));
  h.runFor(ms(200));
  const size_t feedsBefore = wdt.feeds().size();
  EXPECT_EQ(feedsBefore, 4u);
  bStalled = true;
  h.runFor(ms(60));  // task 2 checked in at 200 ms, just before stalling: that window may still feed
  const size_t feedsAtStall = wdt.feeds().size();
  EXPECT_LE(feedsAtStall, feedsBefore + 1);
  h.runFor(ms(500));
  EXPECT_EQ(wdt.feeds().size(), feedsAtStall) << "no feed while task 2 makes no progress";
  EXPECT_GE(wdt.longestGapUs(0), 500000u);
  ASSERT_GT(h.trace.count(TraceKind::WatchdogStarved), 0u);
  for (const auto& r : h.trace.records()) {
    if (r.kind == TraceKind::WatchdogStarved) {
      EXPECT_EQ(r.arg, 1u << 2) << "the starved mask names task 2";
    }
  }
}

TEST(SchedSupervision, WatchdogNotFedWhenAHigherPriorityTaskHogsTheCpu) {
  bsp::host::Harness h;
  bsp::host::SimWatchdog wdt(h.clock);
  FnTask hog, low;
  hog.set([&](fw::sched::EventMask) { h.clock.advance(us(1200)); });  // always ready again: 100 % CPU
  low.set([&](fw::sched::EventMask) { h.sched.checkIn(1); });
  h.sched.addTask(1, low, {}, true);
  h.sched.addTask(6, hog);
  fw::sched::Timer th, tl;
  h.sched.startTimer(tl, 1, 0x1, ms(5), ms(5));
  h.sched.startTimer(th, 6, 0x1, ms(20), ms(1));
  h.sched.superviseWatchdog(wdt, ms(50));
  h.runFor(ms(300));
  // Fed once at 50 ms (the low task checked in at 5, 10, 15 ms before the hog started at 20 ms), then
  // starved: the low task is ready but never runs.
  EXPECT_EQ(wdt.feeds().size(), 1u);
  EXPECT_EQ(h.sched.stats(1).runs, 3u);
  EXPECT_GE(h.trace.count(TraceKind::WatchdogStarved), 4u);
}

}  // namespace
