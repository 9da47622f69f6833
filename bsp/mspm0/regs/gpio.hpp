// GPIO and IOMUX registers. Source: mspm0*.tsv rows "GPIO.*", "GPIO_*", "IOMUX.*", "IOMUX_PINCM_*" and note
// "PINCM index" (MSPM0 TRM IOMUX and GPIO chapters, SLAU846A sections 8 and 9).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::gpio {

// Data registers, 0x1280..0x12E0; the word after each is its 63:32 twin, absent on these parts.
struct Data {
  Reg dout;  // 0x1280 DOUT31_0
  Reg reserved0_[3];
  Reg doutset;  // 0x1290 DOUTSET31_0
  Reg reserved1_[3];
  Reg doutclr;  // 0x12A0 DOUTCLR31_0
  Reg reserved2_[7];
  Reg doe;  // 0x12C0 DOE31_0
  Reg reserved3_[3];
  Reg doeset;  // 0x12D0 DOESET31_0
  Reg reserved4_[3];
  Reg doeclr;  // 0x12E0 DOECLR31_0
};
inline constexpr uintptr_t kDataOffset = 0x1280;
static_assert(kDataOffset + offsetof(Data, doutset) == 0x1290 &&
              kDataOffset + offsetof(Data, doutclr) == 0x12A0);
static_assert(kDataOffset + offsetof(Data, doe) == 0x12C0 && kDataOffset + offsetof(Data, doeset) == 0x12D0);
static_assert(kDataOffset + offsetof(Data, doeclr) == 0x12E0);

struct Input {
  Reg din;  // 0x1380 DIN31_0
  Reg reserved0_[3];
  Reg polarity15_0;  // 0x1390, two bits per pin
  Reg reserved1_[3];
  Reg polarity31_16;  // 0x13A0
};
inline constexpr uintptr_t kInputOffset = 0x1380;
static_assert(kInputOffset + offsetof(Input, polarity15_0) == 0x1390);
static_assert(kInputOffset + offsetof(Input, polarity31_16) == 0x13A0);

inline Data& data(uintptr_t port) {
  return mmio::block<Data>(port + kDataOffset);
}
inline Input& input(uintptr_t port) {
  return mmio::block<Input>(port + kInputOffset);
}

inline constexpr uint32_t kPolarityMask = 3;  // GPIO_POLARITY15_0_DIO0: 1 rise, 2 fall, 3 both

}  // namespace bsp::mspm0::reg::gpio

namespace bsp::mspm0::reg::iomux {

// IOMUX_BASE is the same on the L1306 and the G3507 (tsv base rows); PINCMn (1-based) is at IOMUX_BASE+4n.
inline constexpr uintptr_t kBase = 0x40428000;
inline Reg& pincm(uint32_t index) {
  return mmio::block<Reg>(kBase + 4 * index);
}

inline constexpr uint32_t kPfGpio = 1;  // "GPIO function is always PF=1"
inline constexpr uint32_t kPc = 1U << 7;
inline constexpr uint32_t kPullDown = 1U << 16;
inline constexpr uint32_t kPullUp = 1U << 17;
inline constexpr uint32_t kInputEnable = 1U << 18;
inline constexpr uint32_t kHiZ1 = 1U << 25;  // a driven 1 tri-states the pin: open drain

}  // namespace bsp::mspm0::reg::iomux
