// CPU subsystem interrupt groups and the Cortex-M0+ NVIC, both through the MMIO facade so host tests see
// them. Source: mspm0*.tsv rows "CPUSS.INT_GROUP[n].IIDX" (CPUSS_BASE + 0x1100 + 0x30 * n), "group_iidx";
// the NVIC addresses are those of bsp/cortex_m/scs.hpp (ARMv6-M ARM B3.4).
#pragma once

#include <cstddef>
#include <cstdint>

#include "cortex_m/scs.hpp"
#include "regs/common.hpp"

namespace bsp::mspm0::reg::cpuss {

// INT_GROUP[n] has the layout of an event block; IIDX = pending member (1-based, tsv group_iidx rows).
inline EventBlock& group(uintptr_t cpussBase, uint32_t n) {
  return mmio::block<EventBlock>(cpussBase + 0x1100 + 0x30 * n);
}
// CTL (CPUSS_BASE + 0x1300): PREFETCH bit 0, ICACHE bit 1, LITEN bit 2 (hw_cpuss.h CPUSS_CTL). TI reads the
// factory region with the instruction cache off (dl_factoryregion.h: "disable the cache before TRIM access",
// DL_CORE_PREFETCH_ENABLED | DL_CORE_CACHE_DISABLED | DL_CORE_LITERAL_CACHE_ENABLED), then restores CTL.
inline Reg& ctl(uintptr_t cpussBase) {
  return mmio::block<Reg>(cpussBase + 0x1300);
}
inline constexpr uint32_t kCtlPrefetch = 1U << 0;
inline constexpr uint32_t kCtlLiteralCache = 1U << 2;
inline constexpr uint32_t kGroup1Gpioa = 1;
inline constexpr uint32_t kGroup1Gpiob = 2;

}  // namespace bsp::mspm0::reg::cpuss

namespace bsp::mspm0::nvic {

struct Regs {
  mmio::Reg iser;  // scs::kNvicIser
  mmio::Reg reserved0_[31];
  mmio::Reg icer;  // scs::kNvicIcer
  mmio::Reg reserved1_[31];
  mmio::Reg ispr;  // scs::kNvicIspr
  mmio::Reg reserved2_[31];
  mmio::Reg icpr;  // scs::kNvicIcpr
};
inline constexpr uintptr_t kBase = scs::kNvicIser;
static_assert(kBase + offsetof(Regs, icer) == scs::kNvicIcer &&
              kBase + offsetof(Regs, ispr) == scs::kNvicIspr &&
              kBase + offsetof(Regs, icpr) == scs::kNvicIcpr);

inline Regs& regs() {
  return mmio::block<Regs>(kBase);
}
// Clears a stale pending state, then enables the line (regs/common.cpp).
void enable(uint32_t irq);
inline void setPending(uint32_t irq) {
  regs().ispr.write(1U << irq);
}

}  // namespace bsp::mspm0::nvic
