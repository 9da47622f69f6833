// Data-carrying event queues and the queue-full policy.
#include <gtest/gtest.h>

#include "fn_task.hpp"
#include "sched/event_queue.hpp"
#include "sim/harness.hpp"

namespace {

using fw::sched::QueuePolicy;
using fw::sched::TraceKind;
using test::FnTask;

TEST(SchedQueue, CountAndDropKeepsTheOldestAndCountsTheRest) {
  bsp::host::Harness h;
  FnTask consumer;
  fw::sched::EventQueue<int, 4> queue(h.sched, 2, 0x1, QueuePolicy::CountAndDrop);
  std::vector<int> got;
  consumer.set([&](fw::sched::EventMask) {
    int v;
    while (queue.pop(v))
      got.push_back(v);
  });
  h.sched.addTask(2, consumer);
  const int line = h.irq.attach("can-rx", [&] {
    for (int i = 0; i < 6; ++i)
      queue.post(i);
  });
  h.irq.raise(line);
  h.runUntilIdle();
  EXPECT_EQ(got, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(queue.dropped(), 2u);
  EXPECT_EQ(h.sched.stats(2).queueDrops, 2u);
  EXPECT_EQ(h.trace.count(TraceKind::QueueFull, 2), 2u);
  EXPECT_EQ(consumer.received.size(), 1u) << "six posts of one event coalesce";
}

TEST(SchedQueue, QueueDrainedBetweenBurstsLosesNothing) {
  bsp::host::Harness h;
  FnTask consumer;
  fw::sched::EventQueue<int, 4> queue(h.sched, 0, 0x1, QueuePolicy::Assert);
  int sum = 0;
  consumer.set([&](fw::sched::EventMask) {
    int v;
    while (queue.pop(v))
      sum += v;
  });
  h.sched.addTask(0, consumer);
  for (int burst = 0; burst < 100; ++burst) {
    for (int i = 1; i <= 4; ++i)
      queue.post(i);
    h.runUntilIdle();
  }
  EXPECT_EQ(sum, 100 * 10);
  EXPECT_EQ(queue.dropped(), 0u);
}

TEST(SchedQueueDeathTest, AssertPolicyTreatsAFullQueueAsADesignError) {
  bsp::host::Harness h;
  FnTask consumer;
  h.sched.addTask(0, consumer);
  fw::sched::EventQueue<int, 2> queue(h.sched, 0, 0x1, QueuePolicy::Assert);
  queue.post(1);
  queue.post(2);
  EXPECT_DEATH(queue.post(3), "FW_ASSERT failed: module 2");
}

}  // namespace
