// Register blocks shared by every MSPM0 peripheral: the power/reset controller (GPRCM, at +0x800 in I2C,
// UART, GPIO, TIMG, WWDT) and the interrupt/event blocks (CPU_INT at +0x1020, then the DMA trigger blocks
// every 0x30). Source: mspm0l1306.tsv / mspm0g3507.tsv rows "I2C.GPRCM.*", "UART.CPU_INT.*",
// "UART.DMA_TRIG_RX.*" and note "GPRCM keys" (MSPM0 TRM SLAU846A, "Peripheral power enable control" and
// "Interrupt and event" sections).
#pragma once

#include <cstddef>
#include <cstdint>

#include "mmio.hpp"

namespace bsp::mspm0::reg {

using mmio::Reg;

struct Gprcm {
  Reg pwren;   // +0x00: KEY 31:24 = 0x26, ENABLE bit 0
  Reg rstctl;  // +0x04: KEY 31:24 = 0xB1, RESETSTKYCLR bit 1, RESETASSERT bit 0
  Reg reserved_[3];
  Reg stat;  // +0x14
};
static_assert(sizeof(Gprcm) == 0x18);
inline constexpr uintptr_t kGprcmOffset = 0x800;

inline constexpr uint32_t kPwrenKeyEnable = 0x26000001;
inline constexpr uint32_t kRstctlKeyAssert = 0xB1000003;

// CPU_INT and DMA_TRIGx blocks. IIDX is never read by the drivers: reading it clears the flag it reports
// (i2c_v1 IIDX description), so they read MIS and clear with ICLR exactly the bits they handled.
struct EventBlock {
  Reg iidx;  // +0x00
  Reg reserved0_;
  Reg imask;  // +0x08
  Reg reserved1_;
  Reg ris;  // +0x10
  Reg reserved2_;
  Reg mis;  // +0x18
  Reg reserved3_;
  Reg iset;  // +0x20
  Reg reserved4_;
  Reg iclr;  // +0x28
  Reg reserved5_;
};
static_assert(sizeof(EventBlock) == 0x30);
static_assert(offsetof(EventBlock, imask) == 0x08 && offsetof(EventBlock, mis) == 0x18);
static_assert(offsetof(EventBlock, iset) == 0x20 && offsetof(EventBlock, iclr) == 0x28);
inline constexpr uintptr_t kCpuIntOffset = 0x1020;

inline Gprcm& gprcm(uintptr_t base) {
  return mmio::block<Gprcm>(base + kGprcmOffset);
}
inline EventBlock& cpuInt(uintptr_t base) {
  return mmio::block<EventBlock>(base + kCpuIntOffset);
}

// Power cycles a peripheral into its reset state and enables it (regs/common.cpp). The TRM asks for a few
// bus cycles between PWREN and the first register access.
void resetAndPowerUp(Gprcm& gprcm);

}  // namespace bsp::mspm0::reg
