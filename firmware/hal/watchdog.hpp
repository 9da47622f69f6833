// Watchdog: the hardware timer that resets the MCU unless fed.
//
// Contract: feed() restarts the watchdog period. Only the scheduler's supervisor calls it, and only when
// every watched task has checked in since the previous feed. Callable from task context.
#pragma once

namespace fw::hal {

class Watchdog {
 public:
  void feed() { doFeed(); }

 protected:
  ~Watchdog() = default;

 private:
  virtual void doFeed() = 0;
};

}  // namespace fw::hal
