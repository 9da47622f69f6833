// CPU subsystem interrupt groups and the Cortex-M0+ NVIC, both through the MMIO facade so host tests see
// them. Source: mspm0*.tsv rows "CPUSS.INT_GROUP[n].IIDX" (CPUSS_BASE + 0x1100 + 0x30 * n), "group_iidx",
// "NVIC.*" (ARMv6-M ARM B3.4).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::cpuss {

// INT_GROUP[n] has the layout of an event block; IIDX = pending member (1-based, tsv group_iidx rows).
inline EventBlock& group(uintptr_t cpussBase, uint32_t n) {
  return mmio::block<EventBlock>(cpussBase + 0x1100 + 0x30 * n);
}
inline constexpr uint32_t kGroup1Gpioa = 1;
inline constexpr uint32_t kGroup1Gpiob = 2;

}  // namespace bsp::mspm0::reg::cpuss

namespace bsp::mspm0::nvic {

struct Regs {
  mmio::Reg iser;  // 0xE000E100
  mmio::Reg reserved0_[31];
  mmio::Reg icer;  // 0xE000E180
  mmio::Reg reserved1_[31];
  mmio::Reg ispr;  // 0xE000E200
  mmio::Reg reserved2_[31];
  mmio::Reg icpr;  // 0xE000E280
};
static_assert(offsetof(Regs, icer) == 0x80 && offsetof(Regs, ispr) == 0x100 && offsetof(Regs, icpr) == 0x180);
inline constexpr uintptr_t kBase = 0xE000E100;

inline Regs& regs() {
  return mmio::block<Regs>(kBase);
}
// Clears a stale pending state, then enables the line (regs/common.cpp).
void enable(uint32_t irq);
inline void setPending(uint32_t irq) {
  regs().ispr.write(1U << irq);
}

}  // namespace bsp::mspm0::nvic
