// LP-MSPM0L1306 board with a battery monitor on I2C0 and SLCAN text on the XDS110 back-channel UART
// (images lp-mspm0l1306-bq76952 and lp-mspm0l1306-bq76907).
//
// Wiring (pins from mspm0l1306.tsv; see bsp/mspm0/README.md for the jumpers):
//   I2C0 SDA PA0, SCL PA1 (seed 000 table 2-1, TI's example), bit rate and stretch limit from the image's
//        board_config.hpp; ALERT of the monitor on PA15 (falling edge, internal pull-up: the images set the
//        BQ76952 ALERT active-low open-drain)
//   UART0 TX PA8 -> XDS110 back-channel (SLCAN text; jumpers J16 1:2 and J101 9:10), DMA channel 0;
//   UART0 RX PA9 <- XDS110 back-channel (SLCAN commands; J17 1:2 and J101 7:8), by interrupt
//   button S2 PA14 (falling edge, pull-up), LED PA26: built only with BMS_BOARD_LED_BUTTON=1
//   (mspm0/config.hpp) TIMG0 = scheduler clock (IRQ 16), TIMG1 = its LFCLK reference in STANDBY1
//   (BSP_DEEP_IDLE, IRQ 2, never taken), WWDT0 = watchdog, I2C0 IRQ 24, UART0 IRQ 15,
//   INT_GROUP1 IRQ 1 (GPIOA)
//
// Contract: bringUp() runs once in thread mode, before interrupts are expected: it captures the chip's
// identity and reset cause (system), sets the clocks, powers GPIOA, starts the scheduler clock, the bus, the
// serial port (both directions) and the watchdog, and arms nothing else.
// board() may be called at any time (it returns the statically built board; drivers work after bringUp()).
#pragma once

#include "core/time.hpp"
#include "hal/clock.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/power.hpp"
#include "hal/serial.hpp"
#include "hal/system.hpp"
#include "hal/watchdog.hpp"
#include "mspm0/config.hpp"

namespace image {

struct Board {
  fw::hal::Clock& clock;
  fw::hal::Watchdog& watchdog;
  fw::hal::I2cBus& i2c;            // the battery monitor's bus (I2C0)
  fw::hal::EdgeInput& alert;       // the monitor's ALERT pin
  fw::hal::SerialPort& serial;     // SLCAN text to the PC, SLCAN commands from it
  fw::hal::SystemControl& system;  // chip identity, reset cause, bootloader entry
#if BMS_BOARD_LED_BUTTON
  fw::hal::EdgeInput& button;  // LaunchPad S2
  fw::hal::DigitalOut& led;    // LaunchPad LED
#endif
#if BSP_DEEP_IDLE
  // STANDBY1 between scans (power_policy.hpp), for the scheduler; null on a board without it (the QEMU
  // bench's stand-ins build this image's application on their own board)
  fw::hal::PowerPolicy* power = nullptr;
#endif
};

Board& board();
void bringUp();

// The scheduler feeds the watchdog (1.0 s hardware timeout) every window if all watched tasks checked in.
inline constexpr fw::Duration kWatchdogWindow = fw::ms(250);

}  // namespace image
