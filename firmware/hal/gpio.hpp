// GPIO: edge-interrupt inputs (BQ769x2 ALERT, BQ79616 nFAULT, buttons) and plain outputs (fault line, LED).
//
// Contract
// - EdgeInput::enable(notify) arms the interrupt for the input's configured edge; `notify` is called from ISR
//   context once per edge (edges closer together than the ISR latency may coalesce into one call).
//   level() reads the pin now (true = high). disable() stops further notifications.
// - DigitalOut::set(level) drives the pin; level() returns the last value set. Callable from any context.
#pragma once

#include "hal/notify.hpp"

namespace fw::hal {

class EdgeInput {
 public:
  void enable(const Notify& notify) { doEnable(notify); }
  void disable() { doDisable(); }
  bool level() const { return doLevel(); }

 protected:
  ~EdgeInput() = default;

 private:
  virtual void doEnable(const Notify& notify) = 0;
  virtual void doDisable() = 0;
  virtual bool doLevel() const = 0;
};

class DigitalOut {
 public:
  void set(bool high) { doSet(high); }
  bool level() const { return doLevel(); }

 protected:
  ~DigitalOut() = default;

 private:
  virtual void doSet(bool high) = 0;
  virtual bool doLevel() const = 0;
};

}  // namespace fw::hal
