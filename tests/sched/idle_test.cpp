// Idle: only when nothing is ready, and never with a wake-up lost.
#include <gtest/gtest.h>

#include <vector>

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

TEST(SchedIdle, TheClockIsLeftAloneWhileTheWakeUpForTheEarliestDeadlineIsArmed) {
  // Issue 32: arm the clock's wake-up only when the earliest deadline changes, and do not read the clock on
  // passes that cannot find a timer due.
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(0, task);
  h.sched.startTimer(timer, 0, 0x1, ms(50), ms(50));
  const int quiet = h.irq.attach("quiet", [] {});
  const int busy = h.irq.attach("busy", [&] { h.sched.post(0, 0x2); });
  h.runUntilIdle();
  EXPECT_EQ(h.clock.wakeAts(), 1u);
  const uint64_t reads = h.clock.reads();
  for (int i = 1; i <= 20; ++i)
    h.clock.schedule(uint64_t(i) * 1000, [&] { h.irq.raise(quiet); });  // the bytes of a transfer
  h.clock.schedule(25000, [&] { h.irq.raise(busy); });                  // a completion that posts
  h.runFor(ms(30));
  ASSERT_EQ(task.received.size(), 1u);
  EXPECT_EQ(task.received[0], 0x2u);
  EXPECT_EQ(h.clock.wakeAts(), 1u) << "the earliest deadline never moved";
  // The one task run reads it twice where run-time budgets are built (FW_SCHED_BUDGETS), for its figures.
  EXPECT_EQ(h.clock.reads(), reads + (fw::sched::kBudgets ? 2u : 0u)) << "no pass could find the timer due";
  h.runFor(ms(25));  // the deadline: its wake-up fired, so the clock is read and the next one armed
  ASSERT_EQ(task.received.size(), 2u);
  EXPECT_EQ(task.received[1], 0x1u);
  EXPECT_EQ(h.clock.wakeAts(), 2u);
  // An earlier deadline than the armed one is armed at once.
  fw::sched::Timer sooner;
  h.sched.startTimer(sooner, 0, 0x4, ms(10));
  h.runUntilIdle();
  EXPECT_EQ(h.clock.wakeAts(), 3u);
  h.runFor(ms(10));
  ASSERT_EQ(task.received.size(), 3u);
  EXPECT_EQ(task.received[2], 0x4u);
}

TEST(SchedIdle, OnlyAHandlerThatPostsResumesTheThread) {
  // Sleep-on-exit (firmware/hal/irq.hpp): idle() sets it with interrupts masked before its WFI, so on the
  // target a handler that posts nothing returns straight to sleep; post() clears it, so the Thread runs
  // once a handler made work. The Thread clears it when it runs on, so its tasks are never stopped by it.
  bsp::host::Harness h;
  FnTask task;
  h.sched.addTask(0, task);
  bool quietLeavesItSet = false, busyLeavesItSet = true, quietSeesChipPrepared = false;
  const int quiet = h.irq.attach("quiet", [&] {
    quietLeavesItSet = h.irq.sleepingOnExit();
    quietSeesChipPrepared = h.irq.chipSleepPrepared();
  });
  const int busy = h.irq.attach("busy", [&] {
    h.sched.post(0, 0x1);
    busyLeavesItSet = h.irq.sleepingOnExit();
  });
  h.irq.setIdleProbe([&] { h.irq.raise(quiet); });
  EXPECT_TRUE(h.sched.idle());
  EXPECT_TRUE(quietLeavesItSet) << "a handler that posts nothing returns to sleep";
  EXPECT_FALSE(h.irq.sleepingOnExit()) << "the Thread clears it when it runs on";
  // The chip's preparation for sleeping (hal/irq.hpp chipSleepBegin: the MSPM0's prefetcher off, CPU_ERR_03)
  // lasts through the sleeps sleep-on-exit makes at handler returns, and is undone once the Thread runs on.
  EXPECT_TRUE(quietSeesChipPrepared);
  EXPECT_FALSE(h.irq.chipSleepPrepared());

  h.irq.setIdleProbe([&] { h.irq.raise(busy); });
  EXPECT_TRUE(h.sched.idle());
  EXPECT_FALSE(busyLeavesItSet) << "post() resumes the Thread";
  EXPECT_TRUE(h.sched.dispatchOne());
  EXPECT_EQ(task.received.size(), 1u);
  h.irq.setIdleProbe(nullptr);
}

TEST(SchedIdle, AWakeUpThatPostsCostsTheLoopTwoMaskedSections) {
  // Issue 32: the main loop's pass (runOnce) takes the posted task in one masked section and, with nothing
  // more ready, sleeps in the next. Before, run() called idle() (finding the work), dispatchOne() (the task),
  // dispatchOne() (nothing) and idle() (the sleep), each with its own masked section: four per wake-up.
  bsp::host::Harness h;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(0, task);
  h.sched.startTimer(timer, 0, 0x4, ms(50));  // armed: no pass reads the clock
  const int busy = h.irq.attach("busy", [&] { h.sched.post(0, 0x1); });
  int wakeUps = 1;
  h.irq.setIdleProbe([&] {
    if (wakeUps-- > 0) h.irq.raise(busy);  // the first sleep ends with a completion that posts
  });
  EXPECT_FALSE(h.sched.runOnce()) << "nothing ready: it armed the wake-up and slept";
  ASSERT_TRUE(h.irq.sleeps() >= 1u);
  const uint64_t sections = h.irq.maskedSections();
  const uint64_t sleeps = h.irq.sleeps();
  EXPECT_TRUE(h.sched.runOnce()) << "the posted task";
  EXPECT_FALSE(h.sched.runOnce()) << "nothing more: back to sleep";
  ASSERT_EQ(task.received.size(), 1u);
  EXPECT_EQ(task.received[0], 0x1u);
  EXPECT_EQ(h.irq.sleeps(), sleeps + 1);
  EXPECT_EQ(h.irq.maskedSections(), sections + 2);
  h.irq.setIdleProbe(nullptr);
}

TEST(SchedIdle, RunOnceFiresADueTimerBeforeItRunsAReadyTask) {
  // The loop's order is dispatchOne()'s: due timers first, so a timer's higher-priority task runs first.
  bsp::host::Harness h;
  FnTask low, high;
  std::vector<int> order;
  low.set([&](fw::sched::EventMask) { order.push_back(1); });
  high.set([&](fw::sched::EventMask) { order.push_back(2); });
  fw::sched::Timer timer;
  h.sched.addTask(1, low);
  h.sched.addTask(2, high);
  h.sched.startTimer(timer, 2, 0x1, ms(1));
  h.clock.advance(ms(2));
  h.sched.post(1, 0x1);
  EXPECT_TRUE(h.sched.runOnce());
  EXPECT_TRUE(h.sched.runOnce());
  EXPECT_EQ(order, (std::vector<int>{2, 1}));
}

}  // namespace

namespace {
// A board policy that records what the scheduler asked and, when `deep`, sleeps itself (as the MSPM0
// StandbyIdle does: its own WFI, with interrupts masked and without sleep-on-exit).
class RecordingPolicy final : public fw::hal::PowerPolicy {
 public:
  explicit RecordingPolicy(bsp::host::SimIrq& irq) : irq_(irq) {}
  bool deep = false;
  int calls = 0;
  bool lastTimed = false;
  uint32_t lastDeadline = 0;
  bool maskedWhenAsked = false;
  bool chipPreparedWhenAsked = false;
  bool sleepOnExitAtItsWfi = false;

 private:
  bool doSleep(bool timed, fw::Instant deadline) override {
    ++calls;
    lastTimed = timed;
    lastDeadline = deadline.us;
    maskedWhenAsked = irq_.masked();
    chipPreparedWhenAsked = irq_.chipSleepPrepared();
    if (deep) {
      sleepOnExitAtItsWfi = irq_.sleepingOnExit();
      irq_.waitForInterrupt();
    }
    return deep;
  }
  bsp::host::SimIrq& irq_;
};
}  // namespace

TEST(SchedIdle, ThePowerPolicyIsAskedWithTheEarliestDeadlineAndInterruptsMasked) {
  bsp::host::Harness h;
  RecordingPolicy policy(h.irq);
  FnTask task;
  fw::sched::Timer later, sooner;
  h.sched.addTask(1, task);
  h.sched.setPowerPolicy(policy);
  const uint64_t start = h.clock.nowUs();
  h.sched.startTimer(later, 1, 0x1, ms(9));
  h.sched.startTimer(sooner, 1, 0x2, ms(4));
  const uint64_t sleepsBefore = h.irq.sleeps();
  ASSERT_TRUE(h.sched.idle());
  EXPECT_EQ(policy.calls, 1);
  EXPECT_TRUE(policy.maskedWhenAsked) << "chosen with interrupts masked, like the plain WFI";
  EXPECT_TRUE(policy.lastTimed);
  EXPECT_EQ(policy.lastDeadline, start + 4000) << "the earliest deadline";
  EXPECT_EQ(h.irq.sleeps(), sleepsBefore + 1) << "declined: the scheduler's own WFI";
}

TEST(SchedIdle, APolicyThatSleptItselfLeavesNoPlainSleepAndNoSleepOnExit) {
  bsp::host::Harness h;
  RecordingPolicy policy(h.irq);
  policy.deep = true;
  FnTask task;
  fw::sched::Timer timer;
  h.sched.addTask(1, task);
  h.sched.setPowerPolicy(policy);
  const uint64_t sleepsBefore = h.irq.sleeps();
  ASSERT_TRUE(h.sched.idle());
  EXPECT_EQ(policy.calls, 1);
  EXPECT_FALSE(policy.lastTimed) << "no timer armed: no deadline";
  EXPECT_EQ(h.irq.sleeps(), sleepsBefore + 1) << "one WFI, the policy's";
  EXPECT_FALSE(policy.sleepOnExitAtItsWfi) << "the Thread looks again after whatever woke the core";
  // The chip's preparation (the MSPM0: its prefetcher off, CPU_ERR_03) covers the policy's own sleep too,
  // and is undone once the Thread runs on.
  EXPECT_TRUE(policy.chipPreparedWhenAsked);
  EXPECT_FALSE(h.irq.chipSleepPrepared());
  // The timers still fire: the policy only chooses how the core sleeps.
  h.sched.startTimer(timer, 1, 0x1, ms(3));
  h.runFor(ms(5));
  EXPECT_EQ(task.received.size(), 1u);
  EXPECT_GE(policy.calls, 2);
}

TEST(SchedIdle, NoPolicyIsAskedWhileWorkIsPending) {
  bsp::host::Harness h;
  RecordingPolicy policy(h.irq);
  FnTask task;
  h.sched.addTask(1, task);
  h.sched.setPowerPolicy(policy);
  h.sched.post(1, 0x1);
  EXPECT_FALSE(h.sched.idle());
  EXPECT_EQ(policy.calls, 0);
}
