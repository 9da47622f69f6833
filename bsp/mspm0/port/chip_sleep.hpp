// The MSPM0's work around a sleep (firmware/hal/irq.hpp chipSleepBegin/chipSleepEnd; this folder is on
// fw_port's include path only in the MSPM0 builds, bsp/cortex_m/port/irq_port.hpp includes it).
//
// CPU_ERR_03 (listed for the MSPM0L130x in SLAZ741D/E and the MSPM0G350x in SLAZ742E; its text read in the
// same advisory of SLAZ763 6.3): entering a low-power mode with a prefetch pending, the flash prefetcher can
// fetch all zeros, and code run after the wake-up before an interrupt handler has refilled the prefetcher
// can be corrupted. The advisory is written against the low-power modes, SLEEP0 among them, where every
// image's scheduler idles, and the Thread code after the WFI runs first there (interrupts are masked until
// the scheduler restores them). So the prefetcher is off from before the first WFI until the Thread runs
// again, through every sleep in between (sleep-on-exit puts the core back to sleep at each handler's return
// until one makes work); handlers meanwhile fetch without it: slower, not wrong. (A public MSPM0 HAL,
// embassy-mspm0, suspends the prefetcher across every WFI for the same advisory.)
// CPU_ERR_02 (SLAZ742G): a prefetch disable takes effect only once a pending flash access has finished,
// which a SHUTDNSTORE access completes: SHUTDNSTORE0 is read right after the write.
// Addresses: CPUSS_BASE 0x40400000 + CTL 0x1300 (PREFETCH bit 0, hw_cpuss.h), SYSCTL_BASE 0x400AF000 +
// SHUTDNSTORE0 0x1400 (hw_sysctl_mspm0l11xx_l13xx.h, hw_sysctl_mspm0g1x0x_g3x0x.h), the same on both parts
// (the tsv base rows).
#pragma once

#include <cstdint>

namespace fw::port {

namespace chip {
inline volatile uint32_t& cpussCtl() {
  return *reinterpret_cast<volatile uint32_t*>(0x40400000 + 0x1300);
}
inline constexpr uint32_t kPrefetch = 1U << 0;
inline constexpr uintptr_t kShutdnstore0 = 0x400AF000 + 0x1400;
}  // namespace chip

// Before the sleep, interrupts masked: the prefetcher off; returns CTL as it was.
inline uint32_t chipSleepBegin() {
  const uint32_t ctl = chip::cpussCtl();
  chip::cpussCtl() = ctl & ~chip::kPrefetch;
  (void)*reinterpret_cast<volatile uint32_t*>(chip::kShutdnstore0);
  return ctl;
}
// Once the Thread runs on after the sleep (sleep-on-exit cleared): CTL back as it was.
inline void chipSleepEnd(uint32_t ctl) {
  chip::cpussCtl() = ctl;
}

}  // namespace fw::port
