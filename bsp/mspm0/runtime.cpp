// Target definitions of the runtime helpers described in runtime.hpp. The loops must not be turned back
// into calls to memset/memcpy by the optimiser (that would recurse), hence no-tree-loop-distribute-patterns.
#include "runtime.hpp"

#include <cstddef>
#include <cstdint>

extern "C" {

// Whole words between the unaligned ends: the scan clears every board's record (64 boards on a BQ79616
// chain), where a byte loop took 10 % of the busy cycles (twin profile, 64 devices).
using AliasingWord = uint32_t __attribute__((may_alias));

__attribute__((optimize("no-tree-loop-distribute-patterns"))) void* memset(void* destination, int value,
                                                                           size_t size) {
  auto* d = static_cast<uint8_t*>(destination);
  const auto byte = static_cast<uint8_t>(value);
  for (; size != 0 && (reinterpret_cast<uintptr_t>(d) & 3U) != 0; --size)
    *d++ = byte;
  const uint32_t word = byte * 0x01010101U;
  for (; size >= 4; size -= 4, d += 4)
    *reinterpret_cast<AliasingWord*>(d) = word;
  while (size-- != 0)
    *d++ = byte;
  return destination;
}

__attribute__((optimize("no-tree-loop-distribute-patterns"))) void* memcpy(void* destination,
                                                                           const void* source, size_t size) {
  auto* d = static_cast<uint8_t*>(destination);
  const auto* s = static_cast<const uint8_t*>(source);
  while (size-- != 0)
    *d++ = *s++;
  return destination;
}

// Overlapping copies (the record store's protection log drops its oldest entry, app/store/persistence.cpp):
// a destination below the source is copied forwards, memcpy's byte order above; otherwise backwards.
__attribute__((optimize("no-tree-loop-distribute-patterns"))) void* memmove(void* destination,
                                                                            const void* source, size_t size) {
  auto* d = static_cast<uint8_t*>(destination);
  const auto* s = static_cast<const uint8_t*>(source);
  if (d <= s) return memcpy(destination, source, size);
  while (size-- != 0)
    d[size] = s[size];
  return destination;
}

// RTABI: quotient in r0, remainder in r1, i.e. a 64-bit return value.
uint64_t __aeabi_uidivmod(uint32_t numerator, uint32_t denominator) {
  const auto qr = bsp::mspm0::runtime::udivmod(numerator, denominator);
  return qr.quotient | (static_cast<uint64_t>(qr.remainder) << 32);
}

uint32_t __aeabi_uidiv(uint32_t numerator, uint32_t denominator) {
  return static_cast<uint32_t>(__aeabi_uidivmod(numerator, denominator));
}

// Signed division on the same unsigned loop, instead of libgcc's 460-byte __divsi3. C semantics: the
// quotient truncates toward zero and the remainder takes the numerator's sign (RTABI 4.3.1).
uint64_t __aeabi_idivmod(int32_t numerator, int32_t denominator) {
  const bool negN = numerator < 0;
  const bool negD = denominator < 0;
  const uint32_t n = negN ? 0U - static_cast<uint32_t>(numerator) : static_cast<uint32_t>(numerator);
  const uint32_t d = negD ? 0U - static_cast<uint32_t>(denominator) : static_cast<uint32_t>(denominator);
  const auto qr = bsp::mspm0::runtime::udivmod(n, d);
  const uint32_t q = negN != negD ? 0U - qr.quotient : qr.quotient;
  const uint32_t r = negN ? 0U - qr.remainder : qr.remainder;
  return q | (static_cast<uint64_t>(r) << 32);
}

int32_t __aeabi_idiv(int32_t numerator, int32_t denominator) {
  return static_cast<int32_t>(static_cast<uint32_t>(__aeabi_idivmod(numerator, denominator)));
}

}  // extern "C"
