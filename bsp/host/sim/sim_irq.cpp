#include "sim/sim_irq.hpp"

#include <cstdio>
#include <cstdlib>

#include "port/irq_port.hpp"

namespace bsp::host {

SimIrq& simIrq() {
  static SimIrq instance;
  return instance;
}

int SimIrq::attach(std::string name, Handler handler) {
  lines_.push_back(Line{std::move(name), std::move(handler)});
  return static_cast<int>(lines_.size() - 1);
}

void SimIrq::raise(int line) {
  lines_.at(static_cast<size_t>(line)).pending = true;
  deliverPending();
}

uint32_t SimIrq::save() {
  const uint32_t previous = primask_ ? 1U : 0U;
  primask_ = true;
  ++maskedSections_;
  return previous;
}

void SimIrq::restore(uint32_t saved) {
  primask_ = saved != 0;
  deliverPending();
}

void SimIrq::waitForInterrupt() {
  // Called with interrupts masked. On the target the core sleeps until a line is pending; here the harness
  // owns time, so return and let it advance the clock. A pending line makes WFI a no-op on the target too.
  if (!primask_) {
    std::fprintf(stderr, "SimIrq: waitForInterrupt called with interrupts enabled (lost-wake-up race)\n");
    std::abort();
  }
  ++sleeps_;
}

void SimIrq::sleepOnExit() {
  // The contract (firmware/hal/irq.hpp): set with interrupts masked, right before the wait.
  if (!primask_) {
    std::fprintf(stderr, "SimIrq: sleepOnExit called with interrupts enabled\n");
    std::abort();
  }
  sleepOnExit_ = true;
}

void SimIrq::deliverPending() {
  if (primask_ || inHandler_) return;
  for (bool again = true; again;) {
    again = false;
    for (auto& line : lines_) {
      if (!line.pending) continue;
      line.pending = false;
      ++line.deliveries;
      inHandler_ = true;
      if (line.handler) line.handler();
      inHandler_ = false;
      again = true;
      break;  // restart from the lowest line, as an NVIC re-evaluates priorities after each handler
    }
  }
}

void SimIrq::reset() {
  idleProbe_ = nullptr;
  lines_.clear();
  primask_ = false;
  inHandler_ = false;
  sleeps_ = 0;
  maskedSections_ = 0;
  sleepOnExit_ = false;
  chipSleepPrepared_ = false;
}

}  // namespace bsp::host

extern "C" void fw_sched_idle_probe() {
  bsp::host::simIrq().runIdleProbe();
}

namespace fw::port {

uint32_t irqSave() {
  return bsp::host::simIrq().save();
}
void irqRestore(uint32_t saved) {
  bsp::host::simIrq().restore(saved);
}
void waitForInterrupt() {
  bsp::host::simIrq().waitForInterrupt();
}
void sleepOnExit() {
  bsp::host::simIrq().sleepOnExit();
}
void resumeOnExit() {
  bsp::host::simIrq().resumeOnExit();
}
uint32_t chipSleepBegin() {
  bsp::host::simIrq().chipSleepPrepared(true);
  return 0;
}
void chipSleepEnd(uint32_t) {
  bsp::host::simIrq().chipSleepPrepared(false);
}

}  // namespace fw::port
