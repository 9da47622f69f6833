// Events posted from interrupt handlers.
#include <gtest/gtest.h>

#include "fn_task.hpp"
#include "hal/irq.hpp"
#include "sim/harness.hpp"

namespace {

using fw::sched::TraceKind;
using test::FnTask;
using test::Lines;

TEST(SchedIsr, PostFromIsrWhileATaskRunsIsDeliveredAfterIt) {
  bsp::host::Harness h;
  FnTask worker, handler;
  const int line = h.irq.attach("uart-rx", [&] { h.sched.post(6, 0x10); });
  worker.set([&](fw::sched::EventMask) {
    h.irq.raise(line);  // the interrupt arrives in the middle of the task
    EXPECT_EQ(handler.received.size(), 0u) << "no preemption of a running task by another task";
  });
  h.sched.addTask(1, worker);
  h.sched.addTask(6, handler);
  h.sched.post(1, 0x1);
  h.runUntilIdle();
  EXPECT_EQ(h.trace.compact({TraceKind::Post, TraceKind::Run, TraceKind::RunEnd}),
            (Lines{"post:1", "run:1", "post:6", "runend:1", "run:6", "runend:6"}));
  EXPECT_EQ(handler.received, (std::vector<fw::sched::EventMask>{0x10}));
}

TEST(SchedIsr, IsrNeverRunsInsideACriticalSection) {
  bsp::host::Harness h;
  FnTask task;
  bool isrRan = false;
  bool ranInside = false;
  const int line = h.irq.attach("alert", [&] {
    isrRan = true;
    if (h.irq.masked()) ranInside = true;
  });
  task.set([&](fw::sched::EventMask) {
    {
      fw::hal::CriticalSection cs;
      h.irq.raise(line);
      EXPECT_FALSE(isrRan) << "the handler waits while interrupts are masked";
    }
    EXPECT_TRUE(isrRan) << "and runs as soon as the mask is lifted";
  });
  h.sched.addTask(0, task);
  h.sched.post(0, 0x1);
  h.runUntilIdle();
  EXPECT_TRUE(isrRan);
  EXPECT_FALSE(ranInside);
}

TEST(SchedIsr, NotifierFromBspCompletionPostsTheRightTaskAndEvent) {
  bsp::host::Harness h;
  FnTask a, b;
  h.sched.addTask(2, a);
  h.sched.addTask(3, b);
  const fw::hal::Notify done = h.sched.notifier(3, 0x00800001);
  const int line = h.irq.attach("i2c", [&] { done(); });
  h.irq.raise(line);
  h.runUntilIdle();
  EXPECT_TRUE(a.received.empty());
  EXPECT_EQ(b.received, (std::vector<fw::sched::EventMask>{0x00800001}));
}

// One interrupt for two tasks (the BQ79616 nFAULT: protection and the monitor), in that order. Its Notify
// differs from notifier(b, eb)'s in the function word alone, so re-arming a pin from one to the other without
// disabling it is safe: any mix of the two Notifys' words posts to b, or to a and b.
TEST(SchedIsr, TwoTaskNotifierPostsBothAndSharesTheOneTaskNotifiersWords) {
  bsp::host::Harness h;
  FnTask a, b;
  std::vector<int> order;
  a.set([&](fw::sched::EventMask) { order.push_back(2); });
  b.set([&](fw::sched::EventMask) { order.push_back(1); });
  h.sched.addTask(2, a);
  h.sched.addTask(1, b);
  const fw::hal::Notify one = h.sched.notifier(1, 0x4);
  const fw::hal::Notify two = h.sched.notifier<2, 0x8, 1, 0x4>();
  EXPECT_EQ(two.context, one.context);
  EXPECT_EQ(two.arg, one.arg);
  EXPECT_NE(two.fn, one.fn);
  const int line = h.irq.attach("gpio", [&] { two(); });
  h.irq.raise(line);
  h.runUntilIdle();
  EXPECT_EQ(a.received, (std::vector<fw::sched::EventMask>{0x8}));
  EXPECT_EQ(b.received, (std::vector<fw::sched::EventMask>{0x4}));
  EXPECT_EQ(order, (std::vector<int>{2, 1})) << "the higher priority first";
  // Torn: the old function with the new words posts to b alone, as the one-task Notify does.
  const fw::hal::Notify torn{one.fn, two.context, two.arg};
  torn();
  h.runUntilIdle();
  EXPECT_EQ(a.received.size(), 1u);
  EXPECT_EQ(b.received.size(), 2u);
}

TEST(SchedIsr, BurstOfInterruptsCoalescesIntoOneRunPerEvent) {
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(1, task);
  const int line = h.irq.attach("gpio", [&] { h.sched.post(1, 0x2); });
  for (int i = 0; i < 100; ++i)
    h.irq.raise(line);
  h.runUntilIdle();
  EXPECT_EQ(h.irq.deliveries(line), 100u);
  EXPECT_EQ(task.received, (std::vector<fw::sched::EventMask>{0x2}));
}

}  // namespace
