// LP-MSPM0G3507 board with a BQ79616 daisy chain on a UART and CAN out (image lp-mspm0g3507-bq79616).
//
// Wiring (pins from mspm0g3507.tsv; see bsp/mspm0/README.md):
//   BQ79616 link, chosen by the CMake cache setting BMS_BQ79616_UART:
//     UART0_PA10_PA11 (default, seed 001 table): UART0 TX PA10, RX PA11 (IRQ 15; the LaunchPad's
//                     back-channel jumpers must be removed)
//     UART1_PA8_PA9   (TI's SDK example):        UART1 TX PA8, RX PA9 (IRQ 13)
//     1 Mbaud 8N1, RX on DMA channel 0, TX on DMA channel 1, TIMG6 (IRQ 17) times pings and RX timeouts
//   nFAULT PB0 (falling edge, pull-up), button S2 PB21, LED PB22, fault output PB26 (LED2 red, high = fault)
//   CANFD0 TX PA12, RX PA13 to the TCAN1046, CANCLK = HFXT 40 MHz (PA5/PA6)
//   TIMG0 = scheduler clock (IRQ 16), WWDT0 = watchdog, CANFD0 IRQ 6, INT_GROUP1 IRQ 1 (GPIOB)
//
// Contract: as board_g3507_i2c_can.hpp, with the BQ79616 link in place of the I2C bus.
#pragma once

#include "core/status.hpp"
#include "core/time.hpp"
#include "hal/can_bus.hpp"
#include "hal/clock.hpp"
#include "hal/gpio.hpp"
#include "hal/uart.hpp"
#include "hal/watchdog.hpp"

// The LaunchPad's LED and button S2 are built only for an application that uses them: define
// BMS_BOARD_LED_BUTTON=1 for the image (target_compile_definitions in its image.cmake). The applications of
// these images use neither (their fault indication is the fault output), so they are left out by default.
#ifndef BMS_BOARD_LED_BUTTON
#define BMS_BOARD_LED_BUTTON 0
#endif

namespace image {

struct Board {
  fw::hal::Clock& clock;
  fw::hal::Watchdog& watchdog;
  fw::hal::Uart& bq79616;         // daisy-chain base link, 1 Mbaud, with pings
  fw::hal::EdgeInput& nfault;     // BQ79616 nFAULT
  fw::hal::DigitalOut& faultOut;  // fault output PB26 (high = fault): LED2 red, BoosterPack header
  fw::hal::CanBus& can;           // results out, 500 kbit/s
  fw::Status canStatus;           // set by bringUp()
#if BMS_BOARD_LED_BUTTON
  fw::hal::EdgeInput& button;  // LaunchPad S2
  fw::hal::DigitalOut& led;    // LaunchPad LED
#endif
};

Board& board();
void bringUp();

inline constexpr fw::Duration kWatchdogWindow = fw::ms(250);

}  // namespace image
