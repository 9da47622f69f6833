// LP-MSPM0G3507 board with a battery monitor or gauge on I2C0 and CAN out (images lp-mspm0g3507-bq4050 and
// lp-mspm0g3507-bq76952).
//
// Wiring (pins from mspm0g3507.tsv; see bsp/mspm0/README.md for the jumpers):
//   I2C0 SDA PA0, SCL PA1 (TI's G3507 bq769x2 example; LED1 on PA0 must be disconnected, jumper J4), bit
//        rate and stretch limit from the image's board_config.hpp; ALERT of the monitor on PB0 (falling
//        edge, pull-up)
//   CANFD0 TX PA12, RX PA13 to the TCAN1046 (seed 001), CANCLK = HFXT 40 MHz (PA5/PA6)
//   button S2 PB21 (falling edge, pull-up) and LED PB22 when built (BMS_BOARD_LED_BUTTON) (LED2 channel),
//   fault output PB26 (LED2 red, high = fault) TIMG0 = scheduler clock (IRQ 16), WWDT0 = watchdog, I2C0 IRQ
//   24, CANFD0 IRQ 6, INT_GROUP1 IRQ 1 (GPIOB)
//
// Contract: bringUp() runs once in thread mode: clocks (SYSOSC 32 MHz, HFXT for CAN), GPIO power, the
// scheduler clock, the bus, CAN and the watchdog. `canStatus` says whether CAN came up (Ok) or not (the
// crystal or the MCAN did not start: Timeout / NotReady); CanBus::send then returns NotReady.
#pragma once

#include "core/status.hpp"
#include "core/time.hpp"
#include "hal/can_bus.hpp"
#include "hal/clock.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
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
  fw::hal::I2cBus& i2c;           // the monitor's or gauge's bus (I2C0)
  fw::hal::EdgeInput& alert;      // ALERT (BQ76952) on PB0; unused by the BQ4050 image unless wired
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
