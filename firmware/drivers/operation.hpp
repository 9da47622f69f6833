// How a driver runs a multi-step device exchange inside the cooperative scheduler.
//
// A driver never blocks. Each operation (a scan, a configuration transaction, a FET command, a chain
// bring-up) is a resumable state machine owned by the driver object:
//   1. The owning task calls a start function (e.g. startScan(out)). It returns Status::Ok when the first
//      step has been started, Busy when another operation is still running, or InvalidArgument. Nothing is
//      written to `out` unless the operation ends in Ok.
//   2. The driver starts bus transfers whose completion Notify posts `context.busEvent` to the owning task,
//      and arms its own Timer (posting `context.timerEvent`) for every wait: an echo poll interval, a device
//      settling time, and an overall deadline. Every wait has a bound.
//   3. The owning task forwards those events: `if (events & drv.events()) if (drv.onEvent(events) ==
//      Progress::Done) { Status s = drv.result(); ... }`. Each onEvent() call does one short step (parse,
//      validate, start the next transfer) and returns.
//   4. When the operation ends, result() holds its final Status: Ok only if every transaction of it validated
//      (CRC, checksum, length, echo, PEC, device id). A value is published only from an Ok operation.
// Retries restart the whole transaction from its first byte; drivers count them, and count each failure by
// status, for link statistics.
#pragma once

#include <cstdint>

#include "sched/scheduler.hpp"

namespace fw::drivers {

enum class Progress : uint8_t { Running, Done };

// Where a driver's completions go: the owning task and the two event bits the driver may use.
struct DriverContext {
  sched::Scheduler& scheduler;
  sched::TaskId task;
  sched::EventMask busEvent;
  sched::EventMask timerEvent;

  sched::EventMask events() const { return busEvent | timerEvent; }
  hal::Notify busNotify() const { return scheduler.notifier(task, busEvent); }
};

}  // namespace fw::drivers
