// MSPM0L1306 facts the BSP uses. Every value is a row of ../shared/reference/mspm0/mspm0l1306.tsv (kind in
// brackets): bases [base], IRQ numbers [irq], DMA triggers [dmatrig], pins [pin] and their
// functions [pinfunc]. The memories [mem] are in images/images.cmake.
#pragma once

#include <cstdint>

#include "pin.hpp"

namespace bsp::mspm0::chip {

struct Mspm0l1306 {
  static constexpr uintptr_t kCpuss = 0x40400000;
  static constexpr uintptr_t kDma = 0x4042A000;
  static constexpr uintptr_t kI2c0 = 0x400F0000;
  static constexpr uintptr_t kUart0 = 0x40108000;
  static constexpr uintptr_t kTimg0 = 0x40084000;
  static constexpr uintptr_t kWwdt0 = 0x40080000;

  static constexpr uint8_t kIrqGroup1 = 1;  // GPIOA (IIDX 1), COMP0
  static constexpr uint8_t kIrqUart0 = 15;
  static constexpr uint8_t kIrqTimg0 = 16;
  static constexpr uint8_t kIrqI2c0 = 24;

  static constexpr uint8_t kDmaTrigUart0Tx = 11;

  // Pins of the LP-MSPM0L1306 that the images use.
  static constexpr PinFunction kI2c0SdaPa0{{0, 0, 1}, 3};
  static constexpr PinFunction kI2c0SclPa1{{0, 1, 2}, 3};
  static constexpr PinFunction kUart0TxPa23{{0, 23, 24}, 2};
  static constexpr PinFunction kUart0RxPa22{{0, 22, 23}, 2};
  static constexpr Pin kPa14{0, 14, 15};  // LaunchPad button S2
  static constexpr Pin kPa26{0, 26, 27};  // LaunchPad LED (TI's bq769x2 example)
  // Not in the tsv pin rows: on the L1306 every listed PAn sits on PINCMn+1 (PA0..PA27 above), and PF 1 is
  // always GPIO, so PA15 is PINCM16. Used for the battery monitor's ALERT input; see bsp/mspm0/README.md.
  static constexpr Pin kPa15{0, 15, 16};
};

}  // namespace bsp::mspm0::chip
