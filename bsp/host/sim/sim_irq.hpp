// SimIrq: the host's simulated interrupt controller.
//
// Behaves like a single-priority NVIC with PRIMASK:
// - raise(line) pends the line. If interrupts are unmasked and no handler is running, the handler runs at
//   once, nested inside whatever thread-mode code raised it (as an interrupt preempts a task on the target).
//   If interrupts are masked (a CriticalSection is open) the handler runs when the mask is lifted, never
//   inside the critical section. Handlers do not nest; lines pended during a handler run after it, in line
//   order.
// - fw::port::irqSave/irqRestore/waitForInterrupt (port/irq_port.hpp) map onto this controller.
// There is one controller per process (simIrq()); a harness resets it for each test.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace bsp::host {

class SimIrq {
 public:
  using Handler = std::function<void()>;

  // Registers a handler and returns its line number.
  int attach(std::string name, Handler handler);
  void raise(int line);

  bool masked() const { return primask_; }
  bool inHandler() const { return inHandler_; }
  uint64_t deliveries(int line) const { return lines_.at(static_cast<size_t>(line)).deliveries; }
  const std::string& name(int line) const { return lines_.at(static_cast<size_t>(line)).name; }
  uint64_t sleeps() const { return sleeps_; }
  // fw::port::irqSave calls (critical sections and the scheduler's masked checks) since the reset.
  uint64_t maskedSections() const { return maskedSections_; }
  // The sleep-on-exit state (fw::port::sleepOnExit / resumeOnExit): set, a handler returning to the Thread
  // would put the core back to sleep on the target.
  bool sleepingOnExit() const { return sleepOnExit_; }
  // Between fw::port::chipSleepBegin and chipSleepEnd: the chip's preparation for sleeping is in effect (on
  // the MSPM0 the flash prefetcher is off, bsp/mspm0/port/chip_sleep.hpp).
  bool chipSleepPrepared() const { return chipSleepPrepared_; }
  void chipSleepPrepared(bool on) { chipSleepPrepared_ = on; }

  // Port implementation.
  uint32_t save();
  void restore(uint32_t saved);
  void waitForInterrupt();
  void sleepOnExit();
  void resumeOnExit() { sleepOnExit_ = false; }

  // Called by the scheduler between its last ready check and WFI (interrupts masked); tests raise lines here
  // to hit the lost-wake-up window exactly.
  void setIdleProbe(std::function<void()> probe) { idleProbe_ = std::move(probe); }
  void runIdleProbe() {
    if (idleProbe_) idleProbe_();
  }

  // Drops every line and clears state (between tests).
  void reset();

 private:
  struct Line {
    std::string name;
    Handler handler;
    bool pending = false;
    uint64_t deliveries = 0;
  };
  void deliverPending();

  std::vector<Line> lines_;
  bool primask_ = false;
  bool inHandler_ = false;
  uint64_t sleeps_ = 0;
  uint64_t maskedSections_ = 0;
  bool sleepOnExit_ = false;
  bool chipSleepPrepared_ = false;
  std::function<void()> idleProbe_;
};

SimIrq& simIrq();

}  // namespace bsp::host
