// Timer: a one-shot or periodic software timer that posts an event to a task when it expires.
//
// Contract
// - A Timer is owned by its user (usually a task or driver object) and must outlive its armed period.
// - Arm and disarm only from thread mode (Scheduler::startTimer / stopTimer); expiry is handled in thread
// mode
//   by the scheduler loop, which posts `events` to the target task. Timers never run user code.
// - Periodic timers are drift-free: deadline(k) = first deadline + k * period, whatever the dispatch latency.
//   If whole periods were missed (the CPU was busy longer than a period), they are skipped, not burst, and
//   counted in the task's timerOverruns.
#pragma once

#include <cstdint>

#include "core/time.hpp"
#include "sched/task.hpp"

namespace fw::sched {

class Timer {
 public:
  bool armed() const { return armed_; }
  Instant deadline() const { return deadline_; }

 private:
  friend class Scheduler;
  Timer* next_ = nullptr;
  Instant deadline_{};
  Duration period_{};
  EventMask events_ = 0;
  TaskId task_ = 0;
  bool armed_ = false;
};

}  // namespace fw::sched
