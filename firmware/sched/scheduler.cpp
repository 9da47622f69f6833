#include "sched/scheduler.hpp"

#include "core/assert.hpp"
#include "hal/irq.hpp"

FW_MODULE(fw::Module::Sched);

// Test builds may define FW_SCHED_IDLE_PROBE to run code in the window between the last ready check and the
// WFI (with interrupts masked): the QEMU race test pends an interrupt exactly there.
#ifdef FW_SCHED_IDLE_PROBE
extern "C" void fw_sched_idle_probe();
#define FW_IDLE_WINDOW() fw_sched_idle_probe()
#else
#define FW_IDLE_WINDOW() ((void)0)
#endif

namespace fw::sched {
namespace {

// Highest set bit of a non-zero byte. ARMv6-M has no CLZ, so use a nibble table (16 bytes) instead of a
// loop: two table look-ups at most, constant time.
constexpr uint8_t kLog2Nibble[16] = {0, 0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 3};

inline uint8_t highestBit(uint8_t mask) {
  if constexpr (kMaxTasks <= 4) return kLog2Nibble[mask];  // the ready set fits the low nibble
  return (mask & 0xF0U) != 0 ? static_cast<uint8_t>(4 + kLog2Nibble[mask >> 4]) : kLog2Nibble[mask];
}

constexpr TaskId kSupervisorTask = 0xFE;  // marks the internal watchdog-supervisor timer

}  // namespace

Instant Scheduler::now() const {
  return clock_.now();
}

void Scheduler::addTask(TaskId id, Task& task, Duration budget, bool watched) {
  FW_ASSERT(id < kMaxTasks && state_.tasks[id] == nullptr);
  state_.tasks[id] = &task;
  if (kBudgets) state_.budget[id] = budget;
  if (watched) state_.watched = static_cast<uint8_t>(state_.watched | (1U << id));
}

void Scheduler::post(TaskId id, EventMask events) {
  FW_ASSERT(id < kMaxTasks && state_.tasks[id] != nullptr);
  {
    hal::CriticalSection cs;
    state_.pending[id] |= events;
    state_.ready = static_cast<uint8_t>(state_.ready | (1U << id));
    port::resumeOnExit();  // from a handler: the Thread runs when it returns (idle() let it sleep on)
  }
  trace(TraceKind::Post, id, events);
}

void Scheduler::postThunk(void* self, uint32_t arg) {
  // arg: postArg(id, events).
  static_cast<Scheduler*>(self)->post(static_cast<TaskId>(arg >> 24), arg & 0x00FFFFFFU);
}

hal::Notify Scheduler::notifier(TaskId id, EventMask events) {
  FW_ASSERT(id < kMaxTasks && (events >> 24) == 0);
  return hal::Notify{&Scheduler::postThunk, this, postArg(id, events)};
}

void Scheduler::insertTimer(Timer& timer) {
  // Sorted by deadline; a timer goes after others with the same deadline, so equal deadlines fire in the
  // order they were armed.
  Timer** link = &state_.timers;
  while (*link != nullptr && !isBefore(timer.deadline_, (*link)->deadline_))
    link = &(*link)->next_;
  timer.next_ = *link;
  *link = &timer;
  timer.armed_ = true;
}

void Scheduler::removeTimer(Timer& timer) {
  for (Timer** link = &state_.timers; *link != nullptr; link = &(*link)->next_) {
    if (*link == &timer) {
      *link = timer.next_;
      break;
    }
  }
  timer.next_ = nullptr;
  timer.armed_ = false;
}

void Scheduler::startTimer(Timer& timer, TaskId id, EventMask events, Duration delay, Duration period) {
  FW_ASSERT(id == kSupervisorTask || (id < kMaxTasks && state_.tasks[id] != nullptr));
  if (timer.armed_) removeTimer(timer);
  timer.task_ = id;
  timer.events_ = events;
  timer.period_ = period;
  timer.deadline_ = clock_.now() + delay;
  insertTimer(timer);
}

void Scheduler::stopTimer(Timer& timer) {
  if (timer.armed_) removeTimer(timer);
}

bool Scheduler::nextDeadline(Instant& deadline) const {
  if (state_.timers == nullptr) return false;
  deadline = state_.timers->deadline_;
  return true;
}

void Scheduler::fireDueTimers(Instant now) {
  while (state_.timers != nullptr && isDue(state_.timers->deadline_, now)) {
    Timer& timer = *state_.timers;
    state_.timers = timer.next_;
    timer.next_ = nullptr;
    timer.armed_ = false;
    const bool supervisor = timer.task_ == kSupervisorTask;

    if (supervisor) {
      superviseOnce();
    } else {
      if (timer.period_.us != 0 && (state_.pending[timer.task_] & timer.events_) != 0) {
        // The previous expiry has not been consumed yet: the task is falling behind its period.
        ++state_.stats[timer.task_].timerOverruns;
        trace(TraceKind::TimerOverrun, timer.task_, 1);
      }
      trace(TraceKind::TimerFire, timer.task_, timer.events_);
      post(timer.task_, timer.events_);
    }

    if (timer.period_.us != 0) {
      // Drift-free: the next deadline is a whole period after the previous *deadline*, not after now.
      timer.deadline_ = timer.deadline_ + timer.period_;
      // Whole periods missed are skipped (keeping the phase) rather than fired in a burst. Counted one by one
      // rather than divided (ARMv6-M has no divide instruction, and this is the only division the scheduler
      // would need): once per missed period, which on the target is at most the watchdog timeout over the
      // period, since a main loop held up longer than that resets the MCU.
      uint32_t missed = 0;
      for (; isDue(timer.deadline_, now); ++missed)
        timer.deadline_ = timer.deadline_ + timer.period_;
      if (missed != 0 && !supervisor) {
        state_.stats[timer.task_].timerOverruns += missed;
        trace(TraceKind::TimerOverrun, timer.task_, missed);
      }
      insertTimer(timer);
    }
  }
}

bool Scheduler::dispatchOne() {
  return pass(false);
}

bool Scheduler::runOnce() {
  return pass(true);
}

inline bool Scheduler::pass(bool sleep) {
  // The clock is read only when a timer may be due: while the wake-up armed for the earliest deadline has
  // not fired, none is (most passes: a task posted by an interrupt, its follow-up).
  if (state_.timers != nullptr && !wakeArmedForEarliest()) fireDueTimers(clock_.now());

  TaskId id;
  EventMask events;
  {
    const uint32_t saved = port::irqSave();
    const uint8_t ready = state_.ready;
    if (ready == 0) {
      // Nothing ready: the loop sleeps in this same masked section (one fewer after every wake-up).
      if (sleep) {
        sleepMasked(saved);
      } else {
        port::irqRestore(saved);
      }
      return false;
    }
    id = highestBit(ready);
    events = state_.pending[id];
    state_.pending[id] = 0;
    state_.ready = static_cast<uint8_t>(ready & ~(1U << id));
    port::irqRestore(saved);
  }

  trace(TraceKind::Run, id, events);
  if constexpr (kBudgets) {
    // Two clock reads around the run: only for the run-time figures, so only where they are built.
    const Instant start = clock_.now();
    state_.tasks[id]->run(events);
    noteRun(id, elapsed(start, clock_.now()));
  } else {
    state_.tasks[id]->run(events);
    trace(TraceKind::RunEnd, id, 0);
  }
  return true;
}

inline void Scheduler::noteRun(TaskId id, Duration took) {
  TaskStats& st = state_.stats[id];
  ++st.runs;
  if (took > st.worstRun) st.worstRun = took;
  trace(TraceKind::RunEnd, id, took.us);
  if (state_.budget[id].us != 0 && took > state_.budget[id]) {
    ++st.overruns;
    trace(TraceKind::Overrun, id, took.us);
  }
}

bool Scheduler::idle() {
  return sleepMasked(port::irqSave());
}

inline bool Scheduler::sleepMasked(uint32_t saved) {
  uint32_t chip = 0;
  // Re-check with interrupts masked: anything posted from now on leaves its interrupt pending, and a pending
  // interrupt makes WFI return at once even with PRIMASK set. The handler then runs after irqRestore.
  const bool armed = state_.timers != nullptr && wakeArmedForEarliest();
  const bool work = state_.ready != 0 ||
                    (state_.timers != nullptr && !armed && isDue(state_.timers->deadline_, clock_.now()));
  if (!work) {
    // Armed only when the earliest deadline moved before the armed wake-up, or that wake-up fired (early,
    // or a far deadline's intermediate one).
    if (state_.timers != nullptr && !armed) {
      clock_.wakeAt(state_.timers->deadline_);
      state_.wakeFor = state_.timers->deadline_;
    }
    trace(TraceKind::Idle, kNoTask, 0);
    FW_IDLE_WINDOW();
    // The chip's own preparation (hal/irq.hpp: the MSPM0's prefetcher off), undone below once the Thread
    // runs on: it covers every sleep until then, the ones sleep-on-exit makes at handler returns too.
    chip = port::chipSleepBegin();
    // The board's policy may sleep deeper itself (hal/power.hpp); it then leaves sleep-on-exit clear, so the
    // next idle chooses again after whatever woke the core.
    bool slept = false;
#if FW_SCHED_POWER_POLICY
    if (state_.power != nullptr) {
      const Timer* const first = state_.timers;
      slept = state_.power->sleep(first != nullptr, first != nullptr ? first->deadline_ : Instant{});
    }
#endif
    if (!slept) {
      // Handlers that post nothing (each byte of an I2C transfer, the clock's half-period counts) return
      // straight to sleep: only post() and the clock's alarm resume the Thread (resumeOnExit).
      port::sleepOnExit();
      port::waitForInterrupt();
    }
  }
  port::irqRestore(saved);
  // Here a handler resumed the Thread, or the WFI ended with none taken (ARMv6-M allows a wake-up for no
  // reason, B1.5.19): either way the Thread runs on, and its own handlers must not stop it.
  if (!work) {
    port::resumeOnExit();
    port::chipSleepEnd(chip);
  }
  return !work;
}

void Scheduler::run() {
  // Only an interrupt that made work resumes the Thread (sleepMasked(): sleep-on-exit). A wake-up costs two
  // masked sections: the one that takes the task, and the one that finds nothing more and sleeps (before:
  // dispatchOne() and idle() each had their own, four).
  for (;;)
    runOnce();
}

void Scheduler::superviseWatchdog(hal::Watchdog& watchdog, Duration window) {
  FW_ASSERT(window.us != 0);
  state_.watchdog = &watchdog;
  state_.checkedIn = 0;
  startTimer(state_.supervisor, kSupervisorTask, 0, window, window);
}

void Scheduler::checkIn(TaskId id) {
  state_.checkedIn = static_cast<uint8_t>(state_.checkedIn | (1U << id));
}

inline void Scheduler::superviseOnce() {
  const uint8_t missing = static_cast<uint8_t>(state_.watched & ~state_.checkedIn);
  if (missing == 0) {
    state_.watchdog->feed();
    trace(TraceKind::WatchdogFeed, kNoTask, 0);
  } else {
    trace(TraceKind::WatchdogStarved, kNoTask, missing);
  }
  state_.checkedIn = 0;
}

void Scheduler::noteQueueDrop(TaskId id) {
  uint32_t drops;
  {
    hal::CriticalSection cs;
    drops = ++state_.stats[id].queueDrops;
  }
  trace(TraceKind::QueueFull, id, drops);
}

void Scheduler::setTraceSink([[maybe_unused]] TraceSink* sink) {
#if FW_SCHED_TRACE
  state_.sink = sink;
#endif
}

void Scheduler::trace([[maybe_unused]] TraceKind kind, [[maybe_unused]] uint8_t task,
                      [[maybe_unused]] uint32_t arg) {
#if FW_SCHED_TRACE
  if (state_.sink != nullptr) state_.sink->record(kind, task, arg);
#endif
}

}  // namespace fw::sched
