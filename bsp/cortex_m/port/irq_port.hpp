// ARMv6-M port of the interrupt facade (firmware/hal/irq.hpp), shared by the QEMU and MSPM0 BSPs.
//
// irqSave/irqRestore use PRIMASK (the M0/M0+ have no BASEPRI). waitForInterrupt is entered with PRIMASK=1:
// ARMv6-M WFI still wakes on any pending enabled interrupt, and its handler runs when the caller restores
// PRIMASK, so a wake-up that arrives after the scheduler's last ready check is never lost (ARMv6-M ARM
// B1.5.19, and the same scheme as QP's QV_CPU_SLEEP). The DSB completes outstanding writes (e.g. a
// peripheral register that clears an interrupt) before the core sleeps. sleepOnExit/resumeOnExit: the
// contract of firmware/hal/irq.hpp.
#pragma once

#include <cstdint>

// The chip's own work around a sleep, if its BSP puts a chip_sleep.hpp on the include path (the MSPM0:
// bsp/mspm0/port/chip_sleep.hpp, an erratum of the flash prefetcher); nothing on QEMU.
#if __has_include("chip_sleep.hpp")
#include "chip_sleep.hpp"
#else
namespace fw::port {
inline uint32_t chipSleepBegin() {
  return 0;
}
inline void chipSleepEnd(uint32_t) {}
}  // namespace fw::port
#endif

namespace fw::port {

inline uint32_t irqSave() {
  uint32_t primask;
  __asm volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
  return primask;
}

inline void irqRestore(uint32_t primask) {
  __asm volatile("msr primask, %0" ::"r"(primask) : "memory");
}

inline void waitForInterrupt() {
  __asm volatile("dsb\n\twfi" ::: "memory");
}

// SCR (ARMv6-M ARM B3.2.7, 0xE000ED10): SLEEPONEXIT is bit 1; SEVONPEND (bit 4) and SLEEPDEEP (bit 2) stay 0,
// so the whole register is written, no read-modify-write between the Thread and the handlers that clear it.
inline constexpr uint32_t kScr = 0xE000ED10;
inline constexpr uint32_t kScrSleepOnExit = 1U << 1;

inline void sleepOnExit() {
  *reinterpret_cast<volatile uint32_t*>(kScr) = kScrSleepOnExit;
}

inline void resumeOnExit() {
  *reinterpret_cast<volatile uint32_t*>(kScr) = 0;
}

}  // namespace fw::port
