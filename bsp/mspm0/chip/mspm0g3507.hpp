// MSPM0G3507 facts the BSP uses. Every value is from TI's MSPM0G3507 device header (mspm0-sdk) or
// the LaunchPad user's guide (kind in brackets): bases [base], IRQ numbers [irq], DMA triggers [dmatrig],
// pins [pin] and their functions [pinfunc], LaunchPad wiring [example]. The memories [mem] are in
// images/images.cmake.
#pragma once

#include <cstdint>

#include "pin.hpp"

namespace bsp::mspm0::chip {

struct Mspm0g3507 {
  static constexpr uintptr_t kCpuss = 0x40400000;
  static constexpr uintptr_t kDma = 0x4042A000;
  static constexpr uintptr_t kI2c0 = 0x400F0000;
  static constexpr uintptr_t kUart0 = 0x40108000;
  static constexpr uintptr_t kUart1 = 0x40100000;
  static constexpr uintptr_t kTimg0 = 0x40084000;
  static constexpr uintptr_t kTimg6 = 0x40868000;
  static constexpr uintptr_t kWwdt0 = 0x40080000;
  static constexpr uintptr_t kFlashctl = 0x400CD000;
  static constexpr uintptr_t kCanfd0 = 0x40508000;

  static constexpr uint8_t kIrqGroup1 = 1;  // GPIOA (IIDX 1), GPIOB (IIDX 2), COMPx, TRNG
  static constexpr uint8_t kIrqCanfd0 = 6;
  static constexpr uint8_t kIrqUart1 = 13;
  static constexpr uint8_t kIrqUart0 = 15;
  static constexpr uint8_t kIrqTimg0 = 16;
  static constexpr uint8_t kIrqTimg6 = 17;
  static constexpr uint8_t kIrqI2c0 = 24;

  static constexpr uint8_t kDmaTrigUart0Rx = 17;
  static constexpr uint8_t kDmaTrigUart0Tx = 18;
  static constexpr uint8_t kDmaTrigUart1Rx = 19;
  static constexpr uint8_t kDmaTrigUart1Tx = 20;

  static constexpr PinFunction kI2c0SdaPa0{{0, 0, 1}, 3};
  static constexpr PinFunction kI2c0SclPa1{{0, 1, 2}, 3};
  static constexpr PinFunction kUart0TxPa10{{0, 10, 21}, 2};
  static constexpr PinFunction kUart0RxPa11{{0, 11, 22}, 2};
  static constexpr PinFunction kUart1TxPa8{{0, 8, 19}, 2};
  static constexpr PinFunction kUart1RxPa9{{0, 9, 20}, 2};
  static constexpr PinFunction kCanTxPa12{{0, 12, 34}, 5};
  static constexpr PinFunction kCanRxPa13{{0, 13, 35}, 6};
  static constexpr Pin kHfxinPa5{0, 5, 10};
  static constexpr Pin kHfxoutPa6{0, 6, 11};
  static constexpr Pin kPb0{1, 0, 12};    // BQ79616 nFAULT (TI example), BQ76952 ALERT here
  static constexpr Pin kPb21{1, 21, 49};  // LaunchPad button S2
  static constexpr Pin kPb22{1, 22, 50};  // LaunchPad RGB LED (LED2), one channel
  static constexpr Pin kPb26{1, 26, 57};  // LaunchPad RGB LED (LED2) red channel; fault output of the images
};

}  // namespace bsp::mspm0::chip
