// Board instance and interrupt glue of the LP-MSPM0G3507 I2C + CAN images: every driver object is built at
// compile time (constinit) from the chip facts and the image's board_config.hpp.
#include "board_g3507_i2c_can.hpp"
#include "board_config.hpp"
#include "chip/mspm0g3507.hpp"
#include "gpio.hpp"
#include "i2c.hpp"
#include "mcan.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"
#include "sysclock.hpp"
#include "timg_clock.hpp"
#include "watchdog.hpp"

extern "C" uint32_t __stack_limit__[];

namespace image {
namespace {

using Chip = bsp::mspm0::chip::Mspm0g3507;
using namespace bsp::mspm0;

constexpr I2cTiming kI2cTiming = i2cTiming(kBusClockHz, config::kI2cBitRate, config::kI2cStretchLimitUs);
static_assert(kI2cTiming.valid, "no I2C clock divider gives this bit rate and stretch limit");

constinit TimgClock clock({Chip::kTimg0, Chip::kIrqTimg0, reg::timg::prescalerFor1MHz(kBusClockHz)});
constinit WindowWatchdog watchdog(Chip::kWwdt0, __stack_limit__);
constinit I2cController i2c({Chip::kI2c0, Chip::kIrqI2c0, Chip::kI2c0SdaPa0, Chip::kI2c0SclPa1,
                             config::kI2cBitRate, kI2cTiming});
constinit GpioEdgeInput alert(Chip::kPb0, Edge::Falling, Pull::Up);
#if BMS_BOARD_LED_BUTTON
constinit GpioEdgeInput button(Chip::kPb21, Edge::Falling, Pull::Up);
constinit GpioOut led(Chip::kPb22);
#endif
constinit GpioOut faultOut(Chip::kPb26);
constinit McanBus can({Chip::kCanfd0, Chip::kIrqCanfd0, Chip::kCanTxPa12, Chip::kCanRxPa13,
                       McanBus::kNbtp500k});

constexpr uintptr_t kGpioPorts[] = {kGpioaBase, kGpioaBase + kGpioPortStride};
#if BMS_BOARD_LED_BUTTON
GpioEdgeInput* const kEdgeInputs[] = {&alert, &button};
constinit Board instance{clock, watchdog, i2c, alert, faultOut, can, fw::Status::NotReady, button, led};
#else
GpioEdgeInput* const kEdgeInputs[] = {&alert};
constinit Board instance{clock, watchdog, i2c, alert, faultOut, can, fw::Status::NotReady};
#endif
constinit GpioInterrupts gpioInterrupts(Chip::kCpuss, kGpioPorts, kEdgeInputs);

}  // namespace

Board& board() {
  return instance;
}

void bringUp() {
  initSysosc(true);
  powerGpioPort(kGpioaBase);
  powerGpioPort(kGpioaBase + kGpioPortStride);
  faultOut.init(true);  // asserted until the application has measured the pack and released it
#if BMS_BOARD_LED_BUTTON
  led.init(false);
  button.init();
#endif
  clock.start();
  i2c.init();
  alert.init();
  const fw::Status hfxt = startHfxt(Chip::kHfxinPa5, Chip::kHfxoutPa6);
  instance.canStatus = hfxt == fw::Status::Ok ? can.init() : hfxt;
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
void CANFD0_IRQHandler() {
  image::can.onInterrupt();
}
void GROUP1_IRQHandler() {
  image::gpioInterrupts.onInterrupt();
}
}
