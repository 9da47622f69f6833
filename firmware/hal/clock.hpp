// Clock: the firmware's single time source (microseconds, see core/time.hpp).
//
// Contract
// - now() is monotonic (modulo the 32-bit wrap) and callable from any context, including ISRs.
// - wakeAt(deadline) asks for an interrupt at or after `deadline` so that a sleeping CPU wakes to run timers.
//   If `deadline` is already due, the BSP must pend the wake-up at once (never lose it). A later call
//   replaces the earlier request. Called by the scheduler only, with interrupts masked.
// - A tick-based BSP may wake earlier than asked (e.g. every SysTick); waking early is always allowed.
// - wakeArmed(): true from wakeAt() until the BSP's handler for that wake-up calls wakeFired(): its
//   deadline has not come, or its interrupt is pending and runs as soon as interrupts are unmasked (a WFI
//   then returns at once). A tick-based BSP calls wakeFired() on every tick. The scheduler leaves the clock
//   unread while the wake-up for its earliest deadline is still to come: one load, no virtual call.
#pragma once

#include "core/time.hpp"

namespace fw::hal {

class Clock {
 public:
  // Always inline: a direct virtual call at each of its few callers, and none at all where the clock's type
  // is known and final (the MSPM0 power policy's TimgClock): one call less per read (issue 32).
  [[gnu::always_inline]] Instant now() const { return doNow(); }
  void wakeAt(Instant deadline) {
    // Counted before arming: a wake-up pended at once (the deadline already due) marks this one fired.
    armed_ = static_cast<uint8_t>(armed_ + 1);
    doWakeAt(deadline);
  }
  bool wakeArmed() const { return armed_ != fired_; }

 protected:
  ~Clock() = default;
  // The BSP's handler, for the wake-up wakeAt() armed (or for any tick of a tick-based clock).
  void wakeFired() { fired_ = armed_; }

 private:
  virtual Instant doNow() const = 0;
  virtual void doWakeAt(Instant deadline) = 0;

  // Wake-ups armed (written by the Thread only) and the last one fired (by the handler only): no byte is
  // written on both sides, so no update can be torn by the other. wakeAt() runs with interrupts masked, and
  // arming clears a stale alarm, so a handler that runs after it saw this wake-up's alarm.
  volatile uint8_t armed_ = 0;
  volatile uint8_t fired_ = 0;
};

}  // namespace fw::hal
