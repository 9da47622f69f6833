// Interrupt masking and sleep, provided by the BSP through the port header on its include path.
//
// Contract (each BSP's port/irq_port.hpp implements, in namespace fw::port):
//   uint32_t irqSave();            mask interrupts (PRIMASK=1 on Cortex-M), return the previous state
//   void irqRestore(uint32_t);     restore the state irqSave returned
//   void waitForInterrupt();       sleep until an interrupt is pending. Called with interrupts MASKED: on
//                                  ARMv6-M, WFI wakes on a pending interrupt even with PRIMASK=1, and the
//                                  handler runs once the caller restores the mask, so an interrupt that
//                                  arrives between the caller's last check and the WFI is never lost.
//                                  On the host it returns to the test harness instead of sleeping.
//   void sleepOnExit();            called with interrupts MASKED, right before waitForInterrupt(): from
//                                  now on a handler that returns to Thread mode puts the core back to
//                                  sleep instead of resuming the Thread (ARMv6-M SCR.SLEEPONEXIT), so an
//                                  interrupt that makes no work for the Thread (a byte of a transfer, a
//                                  clock count) costs its handler only, not a pass of the scheduler loop.
//   void resumeOnExit();           the Thread resumes when the current handler returns. Every handler
//                                  that makes work for the Thread calls it (Scheduler::post, a clock's
//                                  alarm); the Thread calls it after its wait too (a wake-up with no
//                                  handler behind it). On the host both only record the state.
//   uint32_t chipSleepBegin();     called with interrupts MASKED before the first sleep of an idle: the
//   void chipSleepEnd(uint32_t);   chip's own preparation (the MSPM0: its flash prefetcher off, an erratum);
//                                  chipSleepEnd, given what Begin returned, undoes it once the Thread runs
//                                  on after resumeOnExit(), so every sleep in between (sleep-on-exit ones
//                                  too) is covered. No-ops where the chip needs nothing.
// CriticalSection is the RAII form; sections nest.
#pragma once

#include <cstdint>

#include "port/irq_port.hpp"

namespace fw::hal {

class CriticalSection {
 public:
  CriticalSection() : saved_(port::irqSave()) {}
  ~CriticalSection() { port::irqRestore(saved_); }
  CriticalSection(const CriticalSection&) = delete;
  CriticalSection& operator=(const CriticalSection&) = delete;

 private:
  uint32_t saved_;
};

}  // namespace fw::hal
