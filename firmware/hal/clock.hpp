// Clock: the firmware's single time source (microseconds, see core/time.hpp).
//
// Contract
// - now() is monotonic (modulo the 32-bit wrap) and callable from any context, including ISRs.
// - wakeAt(deadline) asks for an interrupt at or after `deadline` so that a sleeping CPU wakes to run timers.
//   If `deadline` is already due, the BSP must pend the wake-up at once (never lose it). A later call
//   replaces the earlier request. Called by the scheduler only, with interrupts masked.
// - A tick-based BSP may wake earlier than asked (e.g. every SysTick); waking early is always allowed.
#pragma once

#include "core/time.hpp"

namespace fw::hal {

class Clock {
 public:
  Instant now() const { return doNow(); }
  void wakeAt(Instant deadline) { doWakeAt(deadline); }

 protected:
  ~Clock() = default;

 private:
  virtual Instant doNow() const = 0;
  virtual void doWakeAt(Instant deadline) = 0;
};

}  // namespace fw::hal
