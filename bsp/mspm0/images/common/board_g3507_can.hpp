// LP-MSPM0G3507 board with CAN out and the battery monitor on one of two links, chosen by the image's
// options: I2C0 (images lp-mspm0g3507-bq4050 and lp-mspm0g3507-bq76952) or, with BMS_BOARD_MONITOR_ON_UART=1
// (bsp/mspm0/config.hpp), a BQ79616 daisy chain on a UART (image lp-mspm0g3507-bq79616).
//
// Wiring (pins from mspm0g3507.tsv; see bsp/mspm0/README.md for the jumpers):
//   I2C link: I2C0 SDA PA0, SCL PA1 (TI's G3507 bq769x2 example; LED1 on PA0 must be disconnected, jumper
//        J4), bit rate and stretch limit from board_config.hpp, I2C0 IRQ 24
//   UART link, chosen by the CMake cache setting BMS_BQ79616_UART:
//     UART0_PA10_PA11 (default, seed 001 table): UART0 TX PA10, RX PA11 (IRQ 15; the LaunchPad's
//                     back-channel jumpers must be removed)
//     UART1_PA8_PA9   (TI's SDK example):        UART1 TX PA8, RX PA9 (IRQ 13)
//     1 Mbaud 8N1, RX on DMA channel 0, TX on DMA channel 1, TIMG6 (IRQ 17) times pings and RX timeouts
//   the monitor's ALERT (BQ76952, open-drain) or nFAULT (BQ79616, driven) on PB0 (falling edge, pull-up)
//   CANFD0 TX PA12, RX PA13 to the TCAN1046 (seed 001), CANCLK = HFXT 40 MHz (PA5/PA6); the MCAN's filter
//   receives the command identifiers of the CAN catalogue (fw::can::bms::kReceivedIds) and nothing else
//   button S2 PB21 (falling edge, pull-up) and LED PB22 when built (BMS_BOARD_LED_BUTTON) (LED2 channel),
//   fault output PB26 (LED2 red, high = fault) TIMG0 = scheduler clock (IRQ 16), WWDT0 = watchdog, CANFD0
//   IRQ 6, INT_GROUP1 IRQ 1 (GPIOB)
//
// Contract: bringUp() runs once in thread mode: the chip's identity and reset cause (system), clocks (SYSOSC
// 32 MHz, HFXT for CAN), GPIO power, the
// scheduler clock, the monitor link, CAN and the watchdog. `canStatus` says whether CAN came up (Ok) or not
// (the crystal or the MCAN did not start: Timeout / NotReady); CanBus::send then returns NotReady.
// board() may be called at any time (it returns the statically built board; drivers work after bringUp()).
#pragma once

#include "board_config.hpp"
#include "core/status.hpp"
#include "core/time.hpp"
#include "hal/can_bus.hpp"
#include "hal/clock.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/system.hpp"
#include "hal/uart.hpp"
#include "hal/watchdog.hpp"
#include "mspm0/config.hpp"

namespace image {

struct Board {
  fw::hal::Clock& clock;
  fw::hal::Watchdog& watchdog;
#if BMS_BOARD_MONITOR_ON_UART
  fw::hal::Uart& bq79616;      // daisy-chain base link, 1 Mbaud, with pings
  fw::hal::EdgeInput& nfault;  // BQ79616 nFAULT on PB0
#else
  fw::hal::I2cBus& i2c;       // the monitor's or gauge's bus (I2C0)
  fw::hal::EdgeInput& alert;  // ALERT (BQ76952) on PB0; unused by the BQ4050 image unless wired
#endif
  fw::hal::DigitalOut& faultOut;   // fault output PB26 (high = fault): LED2 red, BoosterPack header
  fw::hal::CanBus& can;            // results out and commands in, 500 kbit/s
  fw::hal::SystemControl& system;  // chip identity, reset cause, bootloader entry
  fw::Status canStatus;            // set by bringUp()
#if BMS_BOARD_LED_BUTTON
  fw::hal::EdgeInput& button;  // LaunchPad S2
  fw::hal::DigitalOut& led;    // LaunchPad LED
#endif
};

Board& board();
void bringUp();

// The scheduler feeds the watchdog every window if all watched tasks checked in.
inline constexpr fw::Duration kWatchdogWindow = fw::ms(250);

}  // namespace image
