// Host port of the interrupt facade (see firmware/hal/irq.hpp): the simulated interrupt controller stands in
// for PRIMASK, and waitForInterrupt() returns to the harness instead of sleeping.
#pragma once

#include <cstdint>

namespace fw::port {

uint32_t irqSave();
void irqRestore(uint32_t saved);
void waitForInterrupt();
void sleepOnExit();
void resumeOnExit();
// No chip work around a sleep on the host.
inline uint32_t chipSleepBegin() {
  return 0;
}
inline void chipSleepEnd(uint32_t) {}

}  // namespace fw::port
