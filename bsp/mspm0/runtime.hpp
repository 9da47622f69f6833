// Size-optimised replacements for the few C runtime helpers the firmware links: memset, memcpy and memmove
// (the compiler emits calls to them for aggregate initialisation and copies; memmove for the record store's
// log, a byte loop either way: newlib's is 176 B) and the EABI division helpers.
// newlib-nano and libgcc ship speed-optimised versions of 166, 142 and 266 bytes. memset writes whole words
// between its unaligned ends: the scans clear their records (64 boards on a BQ79616 chain), and a byte loop
// was 10 % of that image's busy cycles (twin profile; now 3.8 %, +52 B). memcpy stays a byte loop: whole
// words measured -1 % busy cycles on L1306-BQ76952 for +80 B of flash (2026-11-28). Division is bit-serial
// (32 iterations, about 200 cycles): the firmware divides only on rare paths (timer catch-up, unit
// conversions), never per byte.
//
// Contract: the target definitions (runtime.cpp, extern "C") follow the C standard and the ARM RTABI;
// division by zero returns 0 (quotient and remainder), as the RTABI leaves it to the implementation.
// udivmod() is the portable core, host-testable.
#pragma once

#include <cstdint>

namespace bsp::mspm0::runtime {

struct QuotientRemainder {
  uint32_t quotient;
  uint32_t remainder;
};

constexpr QuotientRemainder udivmod(uint32_t n, uint32_t d) {
  if (d == 0) return {0, 0};
  uint32_t q = 0;
  uint32_t r = 0;
  for (int bit = 31; bit >= 0; --bit) {
    const uint32_t carry = r >> 31;  // r << 1 would overflow: the true value is then above any d
    r = (r << 1) | ((n >> bit) & 1U);
    if (carry != 0 || r >= d) {
      r -= d;
      q |= 1U << bit;
    }
  }
  return {q, r};
}

static_assert(udivmod(100, 7).quotient == 14 && udivmod(100, 7).remainder == 2);
static_assert(udivmod(0xFFFFFFFF, 0x80000001).quotient == 1 &&
              udivmod(0xFFFFFFFF, 0x80000001).remainder == 0x7FFFFFFE);

}  // namespace bsp::mspm0::runtime
