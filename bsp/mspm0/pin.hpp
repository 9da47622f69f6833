// Pin: one MSPM0 package pin, named by its GPIO port and bit and by its IOMUX PINCM index.
//
// The PINCM index is not derivable from the port bit on the G3507 (PB0 is PINCM12), so every pin the boards
// use is spelled out in chip/<chip>.hpp from the tsv "pin" rows; peripheral functions (PF values) are per
// pin and listed next to it there. A Pin is 3 bytes: the driver objects that hold pins live in SRAM.
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

// GPIOA_BASE 0x400A0000 and GPIOB_BASE 0x400A2000 on both parts (tsv base rows).
inline constexpr uintptr_t kGpioaBase = 0x400A0000;
inline constexpr uintptr_t kGpioPortStride = 0x2000;

struct Pin {
  uint8_t port = 0;   // 0 = GPIOA, 1 = GPIOB
  uint8_t bit = 0;    // DIO number within the port
  uint8_t pincm = 0;  // 1-based IOMUX PINCM index

  constexpr uint32_t mask() const { return 1U << bit; }
  constexpr uintptr_t portBase() const { return kGpioaBase + kGpioPortStride * port; }
};

// A pin with the peripheral function it is muxed to.
struct PinFunction {
  Pin pin;
  uint8_t pf = 0;
};

}  // namespace bsp::mspm0
