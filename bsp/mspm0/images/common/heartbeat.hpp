// Heartbeat: the placeholder application task of every image until the device drivers and the
// application tasks land. Every period it toggles the LED, emits one output line or frame (the image's
// `emit` function) and checks in with the watchdog supervisor, so a running heartbeat proves the clock,
// the scheduler, the watchdog path and the output bus work.
//
// Contract: start() in thread mode after the scheduler exists; `emit` runs in task context and must not
// block (it starts an asynchronous write or queues a frame and returns).
#pragma once

#include <cstdint>

#include "hal/gpio.hpp"
#include "sched/scheduler.hpp"

namespace image {

class Heartbeat final : public fw::sched::Task {
 public:
  using Emit = void (*)(uint32_t beat);

  constexpr explicit Heartbeat(Emit emit) : emit_(emit) {}

  // Registers the task at priority `id` (watched by the watchdog supervisor) and starts its timer.
  void start(fw::sched::Scheduler& scheduler, fw::sched::TaskId id, fw::hal::DigitalOut& led,
             fw::Duration period);
  void run(fw::sched::EventMask events) override;

 private:
  fw::sched::Scheduler* scheduler_ = nullptr;
  fw::hal::DigitalOut* led_ = nullptr;
  Emit emit_;
  fw::sched::Timer timer_;
  uint32_t beat_ = 0;
  fw::sched::TaskId id_ = 0;
};

// Hex digits of `value` (most significant first) into out[0..digits-1].
void toHex(uint32_t value, uint8_t* out, uint32_t digits);

}  // namespace image
