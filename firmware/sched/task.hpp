// Task: a run-to-completion unit of work with a fixed priority.
//
// Contract
// - run(events) is called by the scheduler in thread mode with the event flags that were pending when the
//   task was picked; those flags are cleared atomically before the call, so a flag posted during run() makes
//   the task ready again and is never lost. Several posts of the same flag before run() coalesce into one.
// - run() must return within the task's budget (Scheduler::addTask) and must never busy-wait on hardware: a
//   multi-step exchange is a state machine that starts the next step, returns, and resumes on the next event.
#pragma once

#include <cstdint>

namespace fw::sched {

using EventMask = uint32_t;
using TaskId = uint8_t;  // also the priority: a higher id runs first

class Task {
 public:
  virtual void run(EventMask events) = 0;

 protected:
  ~Task() = default;
};

}  // namespace fw::sched
