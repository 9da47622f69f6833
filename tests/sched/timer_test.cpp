// One-shot and periodic software timers on virtual time.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fn_task.hpp"
#include "sim/harness.hpp"

namespace {

using fw::ms;
using fw::us;
using fw::sched::TraceKind;
using test::FnTask;

std::vector<uint64_t> runTimes(const bsp::host::TraceRecorder& trace, uint8_t task) {
  std::vector<uint64_t> t;
  for (const auto& r : trace.records()) {
    if (r.kind == TraceKind::Run && r.task == task) t.push_back(r.timeUs);
  }
  return t;
}

TEST(SchedTimer, OneShotFiresOnceAtItsDeadline) {
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(1, task);
  h.sched.startTimer(timer, 1, 0x20, ms(5));
  EXPECT_TRUE(timer.armed());
  h.runFor(ms(50));
  EXPECT_EQ(runTimes(h.trace, 1), (std::vector<uint64_t>{5000}));
  EXPECT_EQ(task.received, (std::vector<fw::sched::EventMask>{0x20}));
  EXPECT_FALSE(timer.armed());
}

TEST(SchedTimer, PeriodicHasNoDriftOver10000Periods) {
  bsp::host::Harness h;
  FnTask task;
  std::mt19937 rng(7);
  // The task consumes a random 0..3 ms of CPU each period: dispatch latency must not accumulate.
  task.set([&](fw::sched::EventMask) { h.clock.advance(us(rng() % 3000)); });
  fw::sched::Timer timer;
  h.sched.addTask(3, task);
  h.sched.startTimer(timer, 3, 0x1, ms(10), ms(10));
  h.runFor(fw::s(100) + ms(5));
  const auto t = runTimes(h.trace, 3);
  ASSERT_EQ(t.size(), 10000u);
  for (size_t k = 0; k < t.size(); ++k)
    ASSERT_EQ(t[k], 10000u * (k + 1)) << "period " << k;
  EXPECT_EQ(h.sched.stats(3).timerOverruns, 0u);
}

TEST(SchedTimer, ManyTimersAtOnceFireInDeadlineOrder) {
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(0, task);
  std::vector<fw::sched::Timer> timers(64);
  std::vector<std::pair<uint64_t, uint32_t>> expected;
  std::mt19937 rng(11);
  for (uint32_t i = 0; i < timers.size(); ++i) {
    const uint32_t delay = 1000 * (1 + rng() % 20);  // many share a deadline
    h.sched.startTimer(timers[i], 0, 1U << (i % 24), us(delay));
    expected.emplace_back(delay, i);
  }
  std::stable_sort(expected.begin(), expected.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<uint64_t, uint32_t>> fired;
  for (const auto& r : h.trace.records())
    (void)r;
  h.runFor(ms(30));
  // Each TimerFire record carries the event bit; map it back through the expected order.
  size_t n = 0;
  for (const auto& r : h.trace.records()) {
    if (r.kind != TraceKind::TimerFire) continue;
    ASSERT_LT(n, expected.size());
    EXPECT_EQ(r.timeUs, expected[n].first) << "timer " << expected[n].second;
    EXPECT_EQ(r.arg, 1U << (expected[n].second % 24)) << "equal deadlines fire in arming order";
    ++n;
  }
  EXPECT_EQ(n, timers.size());
}

TEST(SchedTimer, ManyPeriodicTimersKeepTheirOwnPhase) {
  bsp::host::Harness h;
  FnTask a, b, c;
  h.sched.addTask(1, a);
  h.sched.addTask(2, b);
  h.sched.addTask(3, c);
  fw::sched::Timer ta, tb, tc;
  h.sched.startTimer(ta, 1, 0x1, ms(1), ms(3));
  h.sched.startTimer(tb, 2, 0x1, ms(2), ms(7));
  h.sched.startTimer(tc, 3, 0x1, ms(5), ms(5));
  h.runFor(ms(1000));
  const auto ra = runTimes(h.trace, 1), rb = runTimes(h.trace, 2), rc = runTimes(h.trace, 3);
  ASSERT_EQ(ra.size(), 334u);  // 1 ms + 3 ms * k <= 1000 ms, k = 0..333
  ASSERT_EQ(rb.size(), 143u);
  ASSERT_EQ(rc.size(), 200u);
  for (size_t k = 0; k < ra.size(); ++k)
    EXPECT_EQ(ra[k], 1000 + 3000 * k);
  for (size_t k = 0; k < rb.size(); ++k)
    EXPECT_EQ(rb[k], 2000 + 7000 * k);
  for (size_t k = 0; k < rc.size(); ++k)
    EXPECT_EQ(rc[k], 5000 + 5000 * k);
}

TEST(SchedTimer, StoppedTimerNeverFiresAndRestartReArms) {
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(1, task);
  h.sched.startTimer(timer, 1, 0x1, ms(10), ms(10));
  h.runFor(ms(25));
  h.sched.stopTimer(timer);
  EXPECT_FALSE(timer.armed());
  h.runFor(ms(100));
  EXPECT_EQ(runTimes(h.trace, 1), (std::vector<uint64_t>{10000, 20000}));
  h.sched.startTimer(timer, 1, 0x1, ms(3));  // restart as one-shot from now (125 ms)
  h.runFor(ms(10));
  EXPECT_EQ(runTimes(h.trace, 1).back(), 128000u);
}

TEST(SchedTimer, SlowTaskCountsTimerOverrunsAndSkipsMissedPeriodsWithoutBurst) {
  bsp::host::Harness h;
  FnTask hog, periodic;
  hog.set([&](fw::sched::EventMask) { h.clock.advance(us(35000)); });  // 3.5 periods of CPU
  h.sched.addTask(1, periodic);
  h.sched.addTask(5, hog);
  fw::sched::Timer timer, hogTimer;
  h.sched.startTimer(timer, 1, 0x1, ms(10), ms(10));
  h.sched.startTimer(hogTimer, 5, 0x1, ms(21));  // runs from 21 to 56 ms
  h.runFor(ms(100));
  const auto t = runTimes(h.trace, 1);
  // 10, 20, then the hog; at 56 ms one late run (the 30 ms expiry), 40/50 skipped, then 60, 70, ...
  EXPECT_EQ(t, (std::vector<uint64_t>{10000, 20000, 56000, 60000, 70000, 80000, 90000, 100000}));
  EXPECT_EQ(h.sched.stats(1).timerOverruns, 2u);
  EXPECT_GE(h.trace.count(TraceKind::TimerOverrun, 1), 1u);
}

TEST(SchedTimer, DeadlinesAcrossTheClockWrapAreHonoured) {
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(1, task);
  h.clock.advanceTo((1ULL << 32) - 4500);  // the firmware's 32-bit clock wraps 4.5 ms from now
  fw::sched::Timer timer;
  h.sched.startTimer(timer, 1, 0x1, ms(1), ms(1));
  h.runFor(ms(10));
  const auto t = runTimes(h.trace, 1);
  ASSERT_EQ(t.size(), 10u);
  for (size_t k = 0; k < t.size(); ++k)
    EXPECT_EQ(t[k], (1ULL << 32) - 4500 + 1000 * (k + 1));
}

}  // namespace
