// Bit counting for masks (balancing cell masks, the protection's attempt window).
//
// Contract: countBits(x) is the number of set bits of x, a constexpr loop of one step per set bit. It is
// written out instead of std::popcount / __builtin_popcount because ARMv6-M has no population-count
// instruction and GCC then links libgcc's __popcountsi2 (52 B on the L1306 images, measured), for masks that
// hold a few bits.
#pragma once

#include <cstdint>

namespace fw {

constexpr uint8_t countBits(uint32_t x) {
  uint8_t n = 0;
  for (; x != 0; x &= x - 1)
    ++n;
  return n;
}

static_assert(countBits(0) == 0 && countBits(1) == 1 && countBits(0x8001) == 2 &&
              countBits(0xFFFFFFFFU) == 32);

}  // namespace fw
