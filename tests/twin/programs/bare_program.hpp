// What a twin test program built with the product's start-up (bsp/mspm0/startup.cpp) and linker script needs
// besides its main(): the two-entry vector table (stack top, reset), fw::onFault and the pure-virtual hook,
// both stopping in a loop the test sees as no progress. Included once, by the program's own .cpp.
#pragma once

#include <cstdint>

#include "core/assert.hpp"

extern "C" {
[[noreturn]] void Reset_Handler();
extern uint32_t __stack_top__[];
}

namespace fw {
[[noreturn]] void onFault(Module, uint16_t) {
  for (;;) {
  }
}
}  // namespace fw
extern "C" void __cxa_pure_virtual() {
  for (;;) {
  }
}

using Vector = void (*)();
__attribute__((section(".isr_vector"), used))
const Vector kVectors[2] = {reinterpret_cast<Vector>(__stack_top__), Reset_Handler};
