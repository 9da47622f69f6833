// DMA registers. Source: mspm0*.tsv rows "DMA.*", "DMA_*" and note "DMA" (channel n at DMA_BASE + 0x1200 +
// 0x10 * n; trigger select DMATRIG[n].DMATCTL at DMA_BASE + 0x1110 + 4 * n) - MSPM0 TRM SLAU846A section 6.
// The DMA has no GPRCM: it is always powered.
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::dma {

struct Channel {
  Reg ctl;  // DMACTL
  Reg sa;   // DMASA
  Reg da;   // DMADA
  Reg sz;   // DMASZ: transfers still to do; counts down while the channel runs
};
static_assert(sizeof(Channel) == 0x10);

// Addresses of channel n's registers and of its trigger select DMATRIG[n].DMATCTL (constexpr: DmaChannel
// works them out at compile time for the constinit board objects).
constexpr uintptr_t channelAddress(uintptr_t base, uint32_t n) {
  return base + 0x1200 + 0x10 * n;
}
constexpr uintptr_t triggerSelectAddress(uintptr_t base, uint32_t n) {
  return base + 0x1110 + 4 * n;
}

// DMACTL fields: DMAEN bit 1; DMASRCWDTH/DMADSTWDTH 0 = byte; DMASRCINCR 19:16 and DMADSTINCR 23:20,
// 0x3 = increment, 0x0 = unchanged; DMATM 29:28 = 0 single transfer per trigger.
inline constexpr uint32_t kCtlEnable = 1U << 1;
inline constexpr uint32_t kCtlSrcIncrement = 0x3U << 16;
inline constexpr uint32_t kCtlDstIncrement = 0x3U << 20;

}  // namespace bsp::mspm0::reg::dma
