// constructOnce<T>(args...): builds an image's application object in zero-filled static storage (.bss).
//
// appInit() runs once, from main(), so a function-local static (whose guard variable costs a byte of RAM and
// a test and a store of code) is not needed. The storage is what the reset handler zeroed, which the objects'
// Zeroed state blocks rely on (firmware/core/zeroed.hpp: FW_ZEROED_STORAGE). Call it once per type.
#pragma once

#include <new>

namespace image {

template <class T, class... Args>
T& constructOnce(Args&&... args) {
  alignas(T) static unsigned char storage[sizeof(T)];
  return *new (storage) T(static_cast<Args&&>(args)...);
}

}  // namespace image
