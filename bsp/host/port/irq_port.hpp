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
// The chip's preparation around a sleep: nothing to do on the host; the simulated controller records
// whether it is in effect (SimIrq::chipSleepPrepared), so tests see where the scheduler puts it.
uint32_t chipSleepBegin();
void chipSleepEnd(uint32_t);

}  // namespace fw::port
