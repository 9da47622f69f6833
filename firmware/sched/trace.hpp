// Scheduler trace hook. Host builds (FW_SCHED_TRACE=1) record every scheduling decision so tests can compare
// event sequences; target builds compile the hook out entirely (FW_SCHED_TRACE=0, no code, no RAM).
//
// Contract: record() is called from thread mode and from ISRs (for Post). Arguments per kind:
//   Post            task = target, arg = event mask posted
//   Run             task = task about to run, arg = events it receives
//   RunEnd          task, arg = run time in us
//   Idle            task = 0xFF, arg = 0            (the CPU is about to sleep)
//   TimerFire       task = target, arg = event mask
//   TimerOverrun    task = target, arg = periods missed or not yet consumed
//   QueueFull       task = owner, arg = items dropped so far
//   Overrun         task, arg = run time in us (exceeded its budget)
//   WatchdogFeed    task = 0xFF, arg = 0
//   WatchdogStarved task = 0xFF, arg = bit mask of watched tasks that did not check in
#pragma once

#include <cstdint>

#include "sched/config.hpp"

namespace fw::sched {

enum class TraceKind : uint8_t {
  Post,
  Run,
  RunEnd,
  Idle,
  TimerFire,
  TimerOverrun,
  QueueFull,
  Overrun,
  WatchdogFeed,
  WatchdogStarved,
};

inline constexpr uint8_t kNoTask = 0xFF;

class TraceSink {
 public:
  virtual void record(TraceKind kind, uint8_t task, uint32_t arg) = 0;

 protected:
  ~TraceSink() = default;
};

}  // namespace fw::sched
