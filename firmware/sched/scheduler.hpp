// Scheduler: fixed-priority, run-to-completion tasks driven by events from ISRs and software timers.
//
// Model (QP's QV kernel and RTIC, in a few hundred bytes):
// - Up to kMaxTasks tasks, each with a unique priority (its TaskId; higher runs first), a 32-bit set of
//   pending event flags, and optionally an EventQueue (event_queue.hpp) for data-carrying events.
// - post() sets flags and the task's ready bit; it is the only thing an ISR does.
// - The loop fires due timers, then runs the highest-priority ready task to completion, and repeats. With
//   nothing ready it sleeps race-free: interrupts masked, ready set re-checked, WFI, unmask.
// - Per task: worst run time, run count, budget overruns, timer overruns and queue drops (stats()).
// - Watchdog supervision: the hardware watchdog is fed once per window only if every watched task called
//   checkIn() during that window; one stalled task starves the watchdog and the MCU resets.
//
// Contract
// - addTask/startTimer/stopTimer/checkIn/dispatchOne/idle/runOnce/run: thread mode only.
// - post() and the Notifys from notifier(): any context, including ISRs; O(1), masks interrupts for a few
//   instructions.
// - A programming error (duplicate priority, post to an unregistered task) goes to FW_ASSERT.
// - Run-time measurement is built unless FW_SCHED_BUDGETS is 0 (the images: no task has a budget and nothing
//   reads the figures): each dispatch then reads the clock once (for the timers) instead of three times,
//   addTask() ignores `budget`, and stats().worstRun, runs and overruns stay 0 (the trace's RunEnd carries
//   0).
// - Build options (task slots, run-time measurement, trace): sched/config.hpp.
#pragma once

#include <cstdint>

#include "core/time.hpp"
#include "hal/clock.hpp"
#include "hal/notify.hpp"
#include "hal/power.hpp"
#include "hal/watchdog.hpp"
#include "sched/config.hpp"
#include "sched/task.hpp"
#include "sched/timer.hpp"
#include "sched/trace.hpp"

namespace fw::sched {

inline constexpr uint8_t kMaxTasks = FW_SCHED_MAX_TASKS;
inline constexpr bool kBudgets = FW_SCHED_BUDGETS != 0;

struct TaskStats {
  Duration worstRun{};         // longest single run() so far (FW_SCHED_BUDGETS)
  uint32_t runs = 0;           // completed run() calls (FW_SCHED_BUDGETS)
  uint32_t overruns = 0;       // runs longer than the task's budget (FW_SCHED_BUDGETS)
  uint32_t timerOverruns = 0;  // periodic expiries that found the previous one unconsumed, or were skipped
  uint32_t queueDrops = 0;     // items an EventQueue of this task refused because it was full
};

class Scheduler {
 public:
  // constexpr so an image can declare its scheduler constinit (no static constructor, no init code).
  explicit constexpr Scheduler(hal::Clock& clock) : clock_(clock) {}
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Registers `task` at priority `id`. `budget` is the longest run() allowed before it counts as an overrun
  // (zero: no budget). A `watched` task must checkIn() at least once per watchdog window.
  void addTask(TaskId id, Task& task, Duration budget = {}, bool watched = false);

  // Any context. Sets `events` on task `id` and makes it ready.
  void post(TaskId id, EventMask events);
  // A Notify that posts `events` to task `id` (for BSP completions).
  hal::Notify notifier(TaskId id, EventMask events);
  // A Notify that posts `eventsA` to task `a` and `eventsB` to task `b`, in that order (one interrupt for two
  // tasks: the fault line goes to protection and to the monitor). Checked at compile time; the thunk has the
  // four values as constants. Its context and argument words are those of notifier(b, eventsB), so a pin
  // armed with that one can be re-armed with this one without being disabled first: an interrupt that reads
  // the Notify half-written still gets a valid one (it posts to b alone, as before, or to a and b).
  template <TaskId a, EventMask eventsA, TaskId b, EventMask eventsB>
  hal::Notify notifier() {
    static_assert(a < kMaxTasks && b < kMaxTasks && (eventsB >> 24) == 0, "two task ids, a 24-bit mask");
    return hal::Notify{&Scheduler::postTwoThunk<a, eventsA, b, eventsB>, this, postArg(b, eventsB)};
  }

  // Thread mode. Arms `timer` to post `events` to `id` after `delay`, then every `period` if non-zero.
  // Re-arming an armed timer restarts it.
  void startTimer(Timer& timer, TaskId id, EventMask events, Duration delay, Duration period = {});
  void stopTimer(Timer& timer);

  // Thread mode. Fires due timers, then runs the highest-priority ready task. False if no task ran.
  bool dispatchOne();
  // Thread mode. One pass of run(): dispatchOne(), and with no task ready idle()'s sleep in the same masked
  // section as the ready check. False if no task ran (it slept, or found a timer due or work posted).
  bool runOnce();
  // Thread mode. Sleeps until an interrupt unless work is pending; never loses a wake-up (see irq.hpp).
  // True if it slept, false if work was pending (a ready task or a due timer). With a power policy, the
  // policy may choose a deeper sleep (hal/power.hpp, FW_SCHED_POWER_POLICY); without one, the core's plain
  // sleep.
  bool idle();
#if FW_SCHED_POWER_POLICY
  // Thread mode, before run(). The board's power policy, asked at every idle (none: the plain sleep).
  void setPowerPolicy(hal::PowerPolicy& policy) {
    state_.power = &policy;
  }
#endif
  // The firmware main loop: runOnce() for ever.
  [[noreturn]] void run();

  // Watchdog supervision: every `window`, feed `watchdog` if every watched task checked in, else withhold the
  // feed. The hardware timeout must be longer than `window`.
  void superviseWatchdog(hal::Watchdog& watchdog, Duration window);
  void checkIn(TaskId id);

  // Earliest armed timer deadline, if any timer is armed.
  bool nextDeadline(Instant& deadline) const;
  const TaskStats& stats(TaskId id) const {
    return state_.stats[id];
  }
  hal::Clock& clock() const {
    return clock_;
  }
  // clock().now() as one direct call, for the tasks (out of line: they share it instead of each expanding
  // the virtual call; the scheduler's own hot paths keep the direct virtual call).
  Instant now() const;
  void noteQueueDrop(TaskId id);  // called by EventQueue (any context)

  void setTraceSink(TraceSink* sink);

 private:
  void fireDueTimers(Instant now);
  inline bool pass(bool sleep);  // runOnce() if `sleep`, else dispatchOne()
  // idle() from its masked section on (`saved`: what irqSave() returned); restores the mask.
  inline bool sleepMasked(uint32_t saved);
  // The clock's wake-up is armed for the earliest deadline, or for an earlier time, and has not fired: no
  // timer is due yet. (Armed earlier: the timer it was armed for has stopped, e.g. a bus transaction's
  // timeout. Left armed, it wakes the core once early, and the next transaction's later timeout needs no
  // re-arming: one wake-up armed per scan instead of two per transaction.)
  [[gnu::always_inline]] bool wakeArmedForEarliest() const {
    return clock_.wakeArmed() && !isBefore(state_.timers->deadline_, state_.wakeFor);
  }
  void insertTimer(Timer& timer);
  void removeTimer(Timer& timer);
  inline void superviseOnce();
  inline void noteRun(TaskId id, Duration took);  // the run-time figures (FW_SCHED_BUDGETS)
  void trace(TraceKind kind, uint8_t task, uint32_t arg);
  static void postThunk(void* self, uint32_t arg);
  // postThunk's argument: the task id in the top byte, a 24-bit event mask below it.
  static constexpr uint32_t postArg(TaskId id, EventMask events) {
    return (uint32_t{id} << 24) | events;
  }
  template <TaskId a, EventMask eventsA, TaskId b, EventMask eventsB>
  static void postTwoThunk(void* self, uint32_t) {
    static_cast<Scheduler*>(self)->post(a, eventsA);
    static_cast<Scheduler*>(self)->post(b, eventsB);
  }

  hal::Clock& clock_;
  // Everything else is zero at construction: one block, so an image's scheduler costs no start-up code beyond
  // clearing it (or none, when declared constinit). Byte fields first: Cortex-M0+ byte loads reach only 31
  // bytes past the object's address.
  struct State {
    volatile uint8_t ready;
    uint8_t watched;
    uint8_t checkedIn;
    Instant wakeFor;  // the earliest deadline when idle() last armed the clock's wake-up (its only caller)
    Task* tasks[kMaxTasks];
    EventMask pending[kMaxTasks];
    Duration budget[kMaxTasks];
    TaskStats stats[kMaxTasks];
    Timer* timers;  // armed timers sorted by deadline
    hal::Watchdog* watchdog;
#if FW_SCHED_POWER_POLICY
    hal::PowerPolicy* power;  // null: the plain sleep
#endif
    Timer supervisor;
#if FW_SCHED_TRACE
    TraceSink* sink;
#endif
  };
  State state_{};
};

}  // namespace fw::sched
