// General-purpose timer (TIMG) registers. Source: mspm0*.tsv rows "GPTIMER.*" and "GPTIMER_*"; the
// capture/compare registers (CC at 0x1810, CCCTL at 0x1830) and the CCU bits come from the TIMx register
// description (mspm0-rs/mspm0-data tim_v1.yaml: COUNTERREGS at 0x1800 with the CC array at +0x10 and the
// CCCTL array at +0x30; CPU_INT CCD0 bit 4, CCU0 bit 8) - MSPM0 TRM SLAU846A section 23.
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::timg {

struct Clock {
  Reg clkdiv;  // 0x1000: RATIO 2:0
  Reg reserved_;
  Reg clksel;  // 0x1008: BUSCLK_SEL bit 3
};
inline constexpr uintptr_t kClockOffset = 0x1000;

struct Common {
  Reg reserved_[2];
  Reg cclkctl;  // 0x1108: CLKEN bit 0
  Reg cps;      // 0x110C: PCNT 7:0, divide by PCNT + 1
};
inline constexpr uintptr_t kCommonOffset = 0x1100;

struct Counter {
  Reg ctr;     // 0x1800
  Reg ctrctl;  // 0x1804
  Reg load;    // 0x1808
  Reg reserved0_;
  Reg cc[6];  // 0x1810
  Reg reserved1_[2];
  Reg ccctl[6];  // 0x1830
};
inline constexpr uintptr_t kCounterOffset = 0x1800;
static_assert(kClockOffset + offsetof(Clock, clksel) == 0x1008);
static_assert(kCommonOffset + offsetof(Common, cclkctl) == 0x1108 &&
              kCommonOffset + offsetof(Common, cps) == 0x110C);
static_assert(kCounterOffset + offsetof(Counter, ctrctl) == 0x1804 &&
              kCounterOffset + offsetof(Counter, load) == 0x1808);
static_assert(kCounterOffset + offsetof(Counter, cc) == 0x1810 &&
              kCounterOffset + offsetof(Counter, ccctl) == 0x1830);

inline Clock& clock(uintptr_t base) {
  return mmio::block<Clock>(base + kClockOffset);
}
inline Common& common(uintptr_t base) {
  return mmio::block<Common>(base + kCommonOffset);
}
inline Counter& counter(uintptr_t base) {
  return mmio::block<Counter>(base + kCounterOffset);
}

inline constexpr uint32_t kClkselBusclk = 1U << 3;
inline constexpr uint32_t kClkselLfclk = 1U << 1;  // LFCLK_SEL: 32 768 Hz, counts on in STOP and STANDBY
inline constexpr uint32_t kClockEnable = 1U << 0;

// Power-cycles the timer at `base` and starts its counter clock from BUSCLK /1 with CPS = `prescaler`, in
// the TIMCLK set-up order of the TRM (SLAU846A 23.2.1): source, divider, prescaler, enable. Inline: a
// caller with a constant base and prescaler gets constant register writes.
inline void powerUpClock(uintptr_t base, uint32_t prescaler) {
  resetAndPowerUp(gprcm(base));
  Clock& clk = clock(base);
  clk.clksel.write(kClkselBusclk);
  clk.clkdiv.write(0);  // /1
  Common& com = common(base);
  com.cps.write(prescaler);
  com.cclkctl.write(kClockEnable);
}

// CTRCTL: EN bit 0, REPEAT 3:1, CM 5:4 (0 down, 2 up), CLC/CAC/CZC 9:7/12:10/15:13 must be written 0 (their
// reset value 7 is reserved), CVAE 29:28 (2 = start from zero, 0 = start from LOAD, 1 = no change:
// hw_gptimer.h CTRCTL_CVAE_ZEROVAL / _LDVAL / _NOCHANGE).
inline constexpr uint32_t kCtrEnable = 1U << 0;
inline constexpr uint32_t kCtrRepeat = 1U << 1;  // REPEAT_1: keep counting after a zero event
inline constexpr uint32_t kCtrCountUp = 0x2U << 4;
inline constexpr uint32_t kCtrCountDown = 0x0U << 4;
inline constexpr uint32_t kCtrStartAtZero = 0x2U << 28;
inline constexpr uint32_t kCtrKeepValue = 0x1U << 28;  // CVAE NOCHANGE: counts on from CTR as written
inline constexpr uint32_t kCtrStartAtLoad = 0x0U << 28;

// CPU_INT bits.
inline constexpr uint32_t kIntZero = 1U << 0;
inline constexpr uint32_t kIntLoad = 1U << 1;
inline constexpr uint32_t kIntCcu0 = 1U << 8;
inline constexpr uint32_t kIntCcu1 = 1U << 9;

// CPS value for a 1 MHz counter clock from `busClockHz` (CLKDIV /1).
constexpr uint32_t prescalerFor1MHz(uint32_t busClockHz) {
  return busClockHz / 1000000U - 1U;
}

}  // namespace bsp::mspm0::reg::timg
