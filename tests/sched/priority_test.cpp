// Priority order and event coalescing.
#include <gtest/gtest.h>

#include "fn_task.hpp"
#include "sim/harness.hpp"

namespace {

using fw::sched::TraceKind;
using test::FnTask;
using test::Lines;

TEST(SchedPriority, HighestReadyTaskRunsFirst) {
  bsp::host::Harness h;
  FnTask low, mid, high;
  h.sched.addTask(1, low);
  h.sched.addTask(2, mid);
  h.sched.addTask(5, high);
  h.sched.post(1, 0x1);
  h.sched.post(5, 0x1);
  h.sched.post(2, 0x1);
  h.runUntilIdle();
  EXPECT_EQ(h.trace.compact({TraceKind::Run, TraceKind::Idle}), (Lines{"run:5", "run:2", "run:1", "idle"}));
}

TEST(SchedPriority, RunToCompletionThenHigherPriorityPostedDuringRun) {
  bsp::host::Harness h;
  FnTask low, mid, high;
  low.set([&](fw::sched::EventMask) {
    h.sched.post(7, 0x1);  // a higher-priority task becomes ready while `low` runs
    h.sched.post(3, 0x1);
  });
  h.sched.addTask(1, low);
  h.sched.addTask(3, mid);
  h.sched.addTask(7, high);
  h.sched.post(1, 0x1);
  h.runUntilIdle();
  // No preemption: `low` finishes first, then the highest ready task.
  EXPECT_EQ(h.trace.compact({TraceKind::Run, TraceKind::RunEnd}),
            (Lines{"run:1", "runend:1", "run:7", "runend:7", "run:3", "runend:3"}));
}

TEST(SchedPriority, RepeatedPostsOfOneEventCoalesce) {
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(2, task);
  for (int i = 0; i < 5; ++i)
    h.sched.post(2, 0x4);
  h.runUntilIdle();
  ASSERT_EQ(task.received.size(), 1u);
  EXPECT_EQ(task.received[0], 0x4u);
  EXPECT_EQ(h.trace.count(TraceKind::Post, 2), 5u);
  EXPECT_EQ(h.trace.count(TraceKind::Run, 2), 1u);
}

TEST(SchedPriority, DistinctEventsAccumulateIntoOneRun) {
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(0, task);
  h.sched.post(0, 0x1);
  h.sched.post(0, 0x8);
  h.sched.post(0, 0x100);
  h.runUntilIdle();
  ASSERT_EQ(task.received.size(), 1u);
  EXPECT_EQ(task.received[0], 0x109u);
}

TEST(SchedPriority, EventPostedToSelfDuringRunIsNotLost) {
  bsp::host::Harness h;
  FnTask task;
  int runs = 0;
  task.set([&](fw::sched::EventMask) {
    if (++runs < 3) h.sched.post(4, 0x2);
  });
  h.sched.addTask(4, task);
  h.sched.post(4, 0x1);
  h.runUntilIdle();
  EXPECT_EQ(task.received, (std::vector<fw::sched::EventMask>{0x1, 0x2, 0x2}));
}

TEST(SchedPriorityDeathTest, DuplicatePriorityIsAProgrammingError) {
  bsp::host::Harness h;
  FnTask a, b;
  h.sched.addTask(3, a);
  EXPECT_DEATH(h.sched.addTask(3, b), "FW_ASSERT failed: module 2");
}

TEST(SchedPriorityDeathTest, PostToUnregisteredTaskIsAProgrammingError) {
  bsp::host::Harness h;
  EXPECT_DEATH(h.sched.post(6, 0x1), "FW_ASSERT failed: module 2");
}

}  // namespace
