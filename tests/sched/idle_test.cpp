// Idle: only when nothing is ready, and never with a wake-up lost.
#include <gtest/gtest.h>

#include "fn_task.hpp"
#include "sim/harness.hpp"

namespace {

using fw::ms;
using fw::sched::TraceKind;
using test::FnTask;
using test::Lines;

TEST(SchedIdle, IdleOnlyAfterEveryReadyTaskHasRun) {
  bsp::host::Harness h;
  FnTask a, b;
  a.set([&](fw::sched::EventMask) { h.sched.post(2, 0x1); });  // chain: a makes b ready
  h.sched.addTask(1, a);
  h.sched.addTask(2, b);
  h.sched.post(1, 0x1);
  h.runUntilIdle();
  EXPECT_EQ(h.trace.compact({TraceKind::Run, TraceKind::Idle}), (Lines{"run:1", "run:2", "idle"}));
}

TEST(SchedIdle, NoIdleWhileATimerIsDue) {
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(1, task);
  h.sched.startTimer(timer, 1, 0x1, ms(1));
  h.clock.advance(ms(2));  // the deadline passes without the loop running
  const uint64_t sleepsBefore = h.irq.sleeps();
  h.sched.idle();
  EXPECT_EQ(h.irq.sleeps(), sleepsBefore) << "idle must not sleep over a due timer";
  EXPECT_EQ(h.trace.count(TraceKind::Idle), 0u);
  EXPECT_TRUE(h.sched.dispatchOne());
}

TEST(SchedIdle, IdleArmsTheWakeUpForTheNextDeadline) {
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(1, task);
  h.sched.startTimer(timer, 1, 0x1, ms(7));
  h.runUntilIdle();
  uint64_t next = 0;
  ASSERT_TRUE(h.clock.nextEvent(next));
  EXPECT_EQ(next, 7000u) << "the alarm is the timer's deadline";
  h.runFor(ms(10));
  EXPECT_EQ(task.received.size(), 1u);
}

TEST(SchedIdle, InterruptBetweenReadyCheckAndSleepIsNotLost) {
  // The idle probe runs in the window between the scheduler's last ready check and its WFI. An interrupt
  // raised there must be held pending (interrupts are masked), wake the WFI, run its handler when the mask
  // is lifted, and get its task dispatched with no time passing. The host WFI also aborts if it is ever
  // entered with interrupts enabled, which is what a racy idle would do.
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(0, task);
  const int line = h.irq.attach("late", [&] { h.sched.post(0, 0x1); });
  bool handlerRanInWindow = false;
  h.irq.setIdleProbe([&] {
    const uint64_t before = h.irq.deliveries(line);
    h.irq.raise(line);
    if (h.irq.deliveries(line) != before) handlerRanInWindow = true;
  });
  for (int i = 0; i < 10000; ++i) {
    const uint64_t before = h.clock.nowUs();
    h.runUntilIdle();  // goes idle: the probe raises the interrupt inside the window
    EXPECT_EQ(h.clock.nowUs(), before);
    ASSERT_EQ(task.received.size(), static_cast<size_t>(i)) << "handled by the next dispatch, not lost";
    ASSERT_TRUE(h.sched.dispatchOne()) << "the task is ready without any time passing";
    ASSERT_EQ(task.received.size(), static_cast<size_t>(i + 1));
  }
  EXPECT_FALSE(handlerRanInWindow) << "the handler must not run while interrupts are masked";
  h.irq.setIdleProbe(nullptr);
}

}  // namespace
