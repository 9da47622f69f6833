// Board instance and interrupt glue of the LP-MSPM0L1306 images: every driver object is built at compile
// time (constinit, no constructors run at start-up) from the chip facts and the image's board_config.hpp.
#include "board_l1306_i2c_slcan.hpp"
#include "board_config.hpp"
#include "chip/mspm0l1306.hpp"
#include "gpio.hpp"
#include "i2c.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"
#include "regs/uart.hpp"
#include "sysclock.hpp"
#include "timg_clock.hpp"
#include "uart_serial_tx.hpp"
#include "watchdog.hpp"

extern "C" uint32_t __stack_limit__[];

namespace image {
namespace {

using Chip = bsp::mspm0::chip::Mspm0l1306;
using namespace bsp::mspm0;

constexpr I2cTiming kI2cTiming = i2cTiming(kBusClockHz, config::kI2cBitRate, config::kI2cStretchLimitUs);
static_assert(kI2cTiming.valid, "no I2C clock divider gives this bit rate and stretch limit");

constinit TimgClock clock({Chip::kTimg0, Chip::kIrqTimg0, reg::timg::prescalerFor1MHz(kBusClockHz)});
constinit WindowWatchdog watchdog(Chip::kWwdt0, __stack_limit__);
constinit I2cController i2c({Chip::kI2c0, Chip::kIrqI2c0, Chip::kI2c0SdaPa0, Chip::kI2c0SclPa1,
                             config::kI2cBitRate, kI2cTiming});
constinit GpioEdgeInput alert(Chip::kPa15, Edge::Falling, Pull::Up);
#if BMS_BOARD_LED_BUTTON
constinit GpioEdgeInput button(Chip::kPa14, Edge::Falling, Pull::Up);
constinit GpioOut led(Chip::kPa26);
#endif
constinit UartSerialTx serial({Chip::kUart0, Chip::kIrqUart0,
                               static_cast<uint16_t>(reg::uart::baudDivisor64(kBusClockHz,
                                                                              config::kSlcanBaud)),
                               Chip::kUart0TxPa23, DmaChannel{Chip::kDma, 0, Chip::kDmaTrigUart0Tx}});

constexpr uintptr_t kGpioPorts[] = {kGpioaBase};
#if BMS_BOARD_LED_BUTTON
GpioEdgeInput* const kEdgeInputs[] = {&alert, &button};
constinit Board instance{clock, watchdog, i2c, alert, serial, button, led};
#else
GpioEdgeInput* const kEdgeInputs[] = {&alert};
constinit Board instance{clock, watchdog, i2c, alert, serial};
#endif
constinit GpioInterrupts gpioInterrupts(Chip::kCpuss, kGpioPorts, kEdgeInputs);

}  // namespace

Board& board() {
  return instance;
}

void bringUp() {
  initSysosc(false);
  powerGpioPort(kGpioaBase);
  clock.start();
  i2c.init();
  alert.init();
  serial.init();
#if BMS_BOARD_LED_BUTTON
  led.init(false);
  button.init();
#endif
  bsp::mspm0::nvic::enable(Chip::kIrqGroup1);
  watchdog.start();
}

}  // namespace image

extern "C" {
void TIMG0_IRQHandler() {
  image::clock.onInterrupt();
}
void I2C0_IRQHandler() {
  image::i2c.onInterrupt();
}
void UART0_IRQHandler() {
  image::serial.onInterrupt();
}
void GROUP1_IRQHandler() {
  image::gpioInterrupts.onInterrupt();
}
}
