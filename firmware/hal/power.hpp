// PowerPolicy: the board's choice of how deep the MCU sleeps when the scheduler has nothing to do.
//
// Contract
// - sleep(timed, deadline): called by the scheduler's idle only, in thread mode with interrupts masked,
//   after its last check found no task ready and no timer due, and after it armed the clock's wake-up for
//   the earliest timer deadline (`timed`; `deadline` is that deadline, meaningless when !timed).
//   Either the policy sleeps itself in a mode deeper than the core's plain sleep, until an interrupt is
//   pending, and returns true: by then the clock reads the right time again, the wake-up for `deadline` is
//   still armed (or pended if due), sleep-on-exit was not set (the scheduler looks again after the handler
//   that woke the core) and the core's next sleep is a plain one unless the policy chooses again. Or it
//   does nothing and returns false: the scheduler sleeps as it always does (sleep-on-exit, WFI).
// - It must never lose a wake-up: a mode is chosen only where every event the firmware waits for (a
//   transfer in flight, the deadline, an input edge, a byte arriving) still arrives, and the deadline
//   arrives on time.
// - A board without a policy (the host, QEMU, the G3507 images) passes none to the scheduler.
#pragma once

#include "core/time.hpp"

namespace fw::hal {

class PowerPolicy {
 public:
  bool sleep(bool timed, Instant deadline) { return doSleep(timed, deadline); }

 protected:
  ~PowerPolicy() = default;

 private:
  virtual bool doSleep(bool timed, Instant deadline) = 0;
};

}  // namespace fw::hal
