// Notify: how a BSP completion (ISR context) tells firmware that something finished.
//
// Contract
// - A Notify is a plain function pointer plus two words of context; calling an empty Notify does nothing.
// - BSPs call it from ISR context after the result of the operation has been stored where the caller can
//   read it, so the callee must only post (set a flag, push to a queue) and return. The scheduler hands out
//   Notifies that post an event to a task (Scheduler::notifier()).
#pragma once

#include <cstdint>

namespace fw::hal {

struct Notify {
  void (*fn)(void* context, uint32_t arg) = nullptr;
  void* context = nullptr;
  uint32_t arg = 0;

  void operator()() const {
    if (fn != nullptr) fn(context, arg);
  }
  explicit operator bool() const { return fn != nullptr; }
};

}  // namespace fw::hal
