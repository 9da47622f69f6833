// MSPM0L1306 facts the BSP uses. Every value is from TI's MSPM0L1306 device header (mspm0-sdk) or
// the LaunchPad user's guide (kind in brackets): bases [base], IRQ numbers [irq], DMA triggers [dmatrig],
// pins [pin] and their functions [pinfunc]. The memories [mem] are in images/images.cmake.
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
  static constexpr uintptr_t kTimg1 = 0x40086000;
  static constexpr uintptr_t kWwdt0 = 0x40080000;
  static constexpr uintptr_t kFlashctl = 0x400CD000;

  static constexpr uint8_t kIrqGroup1 = 1;  // GPIOA (IIDX 1), COMP0
  static constexpr uint8_t kIrqUart0 = 15;
  static constexpr uint8_t kIrqTimg0 = 16;
  static constexpr uint8_t kIrqTimg1 = 2;
  static constexpr uint8_t kIrqI2c0 = 24;

  static constexpr uint8_t kDmaTrigUart0Tx = 11;

  // Pins of the LP-MSPM0L1306 that the images use.
  static constexpr PinFunction kI2c0SdaPa0{{0, 0, 1}, 3};
  static constexpr PinFunction kI2c0SclPa1{{0, 1, 2}, 3};
  // The XDS110 back-channel UART (tsv note "LP-MSPM0L1306 backchannel UART"): UART0 TX on PA8 = PINCM9, PF 2
  // (mspm0l130x.h IOMUX_PINCM9_PF_UART0_TX), RX on PA9 = PINCM10, PF 2 (IOMUX_PINCM10_PF_UART0_RX).
  static constexpr PinFunction kUart0TxPa8{{0, 8, 9}, 2};
  static constexpr PinFunction kUart0RxPa9{{0, 9, 10}, 2};
  static constexpr Pin kPa14{0, 14, 15};  // LaunchPad button S2
  static constexpr Pin kPa26{0, 26, 27};  // LaunchPad LED (TI's bq769x2 example)
  // The battery monitor's ALERT input: PA15 = PINCM16, GPIO PF 1 (mspm0l130x.h IOMUX_PINCM16_PF_GPIOA_DIO15;
  // not in the tsv pin rows). See bsp/mspm0/README.md for its LaunchPad jumper.
  static constexpr Pin kPa15{0, 15, 16};
};

}  // namespace bsp::mspm0::chip
