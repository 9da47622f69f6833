// Zeroed<T>: a member block that is all-zero when its owner is constructed, at no code cost on the images.
//
// Every task and driver keeps what changes at run time in one block of trivially copyable fields whose
// empty value is zero (counters, flags, timers, buffers). Value-initialising those blocks (`State state_{}`)
// makes each constructor clear them, one memset or a run of stores per block: on the L1306 image that was
// about a tenth of the application's constructor. On the MSPM0 images every such object is constructed once,
// in static storage (image::constructOnce in the image's appInit()), and static storage is
// already zero: the reset handler clears .bss before main() (bsp/mspm0/startup.cpp). So there the block is
// left as it is, and elsewhere (host tests and tools construct these objects on the stack and the heap) it
// is cleared as before. Measured under link-time optimisation: 228 B of the L1306-BQ76952 image, 192 B of
// the G3507-BQ79616 (built with FW_ZEROED_STORAGE=0 for comparison).
//
// Contract
// - FW_ZEROED_STORAGE (core/config.hpp; the MSPM0 BSP sets it for its images, never an image option): 1 =
//   every object holding a Zeroed<T> is constructed exactly once in zero-filled static storage. An object on
//   the stack or built twice would start from garbage. The twin catches that: it fills SRAM with a
//   pseudo-random pattern at power-up, as real SRAM, so only .bss is zero (bsp/twin/machine.cpp), and runs
//   every image.
// - T is trivially copyable and trivially destructible, and all-zero bytes are its empty value (integers,
//   bools, enums with a zero member, pointers, spans, Instant/Duration).
// - The block lives in an unsigned char array: its bytes may be accessed as T (the array provides storage
//   for an object of implicit-lifetime type T; GCC lets char storage alias any type). std::launder is left
//   out on purpose: it is an optimisation barrier in GCC and cost 200 B on the L1306 image.
#pragma once

#include <cstring>
#include <type_traits>

#include "core/config.hpp"

namespace fw {

template <class T>
class Zeroed {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                "a Zeroed block holds plain data whose empty value is all-zero bytes");

 public:
  Zeroed() {
    if constexpr (!FW_ZEROED_STORAGE) std::memset(bytes_, 0, sizeof bytes_);
  }
  Zeroed(const Zeroed&) = delete;
  Zeroed& operator=(const Zeroed&) = delete;

  T* operator->() { return reinterpret_cast<T*>(bytes_); }
  const T* operator->() const { return reinterpret_cast<const T*>(bytes_); }
  T& operator*() { return *operator->(); }
  const T& operator*() const { return *operator->(); }

 private:
  alignas(T) unsigned char bytes_[sizeof(T)];
};

// The block's address while its own constructor has not run yet (wiring a member declared after the one being
// built): a pointer conversion only, no member of the block is touched.
template <class T>
T* addressOf(Zeroed<T>& block) {
  static_assert(std::is_standard_layout_v<Zeroed<T>>, "the block's bytes start at its address");
  return reinterpret_cast<T*>(&block);
}

}  // namespace fw
