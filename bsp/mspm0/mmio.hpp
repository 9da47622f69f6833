// MMIO facade: the only way MSPM0 driver code touches a peripheral register.
//
// A peripheral's registers are grouped into small blocks (structs of `mmio::Reg` at the TRM offsets, each
// offset checked by a static_assert against the tsv in regs/*.hpp), overlaid on `base + block offset` with
// `mmio::block<T>(address)`. Drivers keep the base in their configuration, so a test can place a
// peripheral anywhere; the chip headers (chip/*.hpp) hold the real bases.
//
// Contract
// - Reg::read() / Reg::write(v) are single 32-bit accesses, in program order, never merged, split or elided.
//   On the target (no BSP_MSPM0_MMIO_MODEL) a Reg is a volatile word. Blocks are at most 128 bytes so that
//   an access is one 2-byte LDR/STR with the offset in the instruction once the block address is in a
//   register; read32(base + offset) would cost a literal word and an ADD per access on Thumb-1, about
//   twice the code, and one struct spanning the whole peripheral makes GCC do the same.
// - With BSP_MSPM0_MMIO_MODEL=1 (host tests) a Reg holds no data: read()/write() call the register-block
//   model (tests/bsp_mspm0/mmio_model.*) with the register's own address, which the model records and
//   answers from scripted values. The overlay pointer is never dereferenced on the host.
// - address(p) turns a pointer into the 32-bit bus address a DMA register wants (on the host the low 32
//   bits, which the model records but never dereferences).
// - spin(n) busy-waits about 4*n CPU cycles; the model records it instead. It exists only for sub-10 us
//   settling gaps of error paths (I2C bus recovery) and power-up, never for normal operation.
// All of it is ISR-safe (single loads and stores); read-modify-write helpers are not atomic.
#pragma once

#include <cstdint>

namespace bsp::mspm0::mmio {

#if defined(BSP_MSPM0_MMIO_MODEL) && BSP_MSPM0_MMIO_MODEL
uint32_t read32(uintptr_t address);
void write32(uintptr_t address, uint32_t value);
void spin(uint32_t iterations);

class Reg {
 public:
  uint32_t read() const { return read32(reinterpret_cast<uintptr_t>(this)); }
  void write(uint32_t value) { write32(reinterpret_cast<uintptr_t>(this), value); }

 private:
  uint32_t unused_;  // gives the register its 4 bytes in the layout; never accessed
};
#else
class Reg {
 public:
  uint32_t read() const { return value_; }
  void write(uint32_t value) { value_ = value; }

 private:
  volatile uint32_t value_;
};

// SUB (flag-setting in the divided syntax GCC uses for Thumb-1 inline asm) + BNE: 4 cycles per iteration on
// a Cortex-M0+ running from zero-wait-state flash.
inline void spin(uint32_t iterations) {
  if (iterations == 0) return;
  __asm volatile("1: sub %0, #1\n\tbne 1b" : "+l"(iterations)::"cc");
}
#endif

static_assert(sizeof(Reg) == 4);

template <class Block>
inline Block& block(uintptr_t base) {
  return *reinterpret_cast<Block*>(base);
}

inline void setBits(Reg& reg, uint32_t bits) {
  reg.write(reg.read() | bits);
}
inline void clearBits(Reg& reg, uint32_t bits) {
  reg.write(reg.read() & ~bits);
}
inline void modify(Reg& reg, uint32_t clear, uint32_t set) {
  reg.write((reg.read() & ~clear) | set);
}

inline uint32_t address(const volatile void* p) {
  return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(p));
}

}  // namespace bsp::mspm0::mmio
