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

}  // namespace fw::port
