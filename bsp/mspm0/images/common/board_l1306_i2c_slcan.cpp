// Board instance and interrupt glue of the LP-MSPM0L1306 images: every driver object is built at compile
// time (constinit, no constructors run at start-up) from the chip facts and the image's board_config.hpp.
#include "board_l1306_i2c_slcan.hpp"
#include "board_config.hpp"
#include "chip/mspm0l1306.hpp"
#include "gpio.hpp"
#include "i2c.hpp"
#include "power_policy.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"
#include "regs/uart.hpp"
#include "sysclock.hpp"
#include "system.hpp"
#include "timg_clock.hpp"
#include "uart_serial.hpp"
#include "watchdog.hpp"

extern "C" uint32_t __stack_limit__[];

namespace image {
namespace {

using Chip = bsp::mspm0::chip::Mspm0l1306;
using namespace bsp::mspm0;

constexpr I2cTiming kI2cTiming = i2cTiming(kBusClockHz, config::kI2cBitRate, config::kI2cStretchLimitUs);
static_assert(kI2cTiming.valid, "no I2C clock divider gives this bit rate and stretch limit");

// Set-up of the clock and the serial output runs from their constant configurations (inline static start()
// and init()), so its register writes are constants.
constexpr TimgClock::Config kClockConfig{Chip::kTimg0, Chip::kIrqTimg0,
                                         reg::timg::prescalerFor1MHz(kBusClockHz)};
constinit TimgClock clock(kClockConfig);
constinit WindowWatchdog watchdog(Chip::kWwdt0, __stack_limit__);
constinit I2cController i2c({Chip::kI2c0, Chip::kIrqI2c0, Chip::kI2c0SdaPa0, Chip::kI2c0SclPa1,
                             config::kI2cBitRate, kI2cTiming});
// Set-up runs on constexpr copies of the inputs (their init() is const and inline), so its register writes
// are constants.
// ALERT: the BQ769x2-family images set the monitor's ALERT pin active-low, open-drain, so the input takes the
// falling edge and the internal pull-up (IOMUX PINCM.PIPU, bit 17; hw_iomux.h IOMUX_PINCM_PIPU).
constexpr GpioEdgeInput kAlert(Chip::kPa15, Edge::Falling, Pull::Up);
constinit GpioEdgeInput alert = kAlert;
#if BMS_BOARD_LED_BUTTON
constexpr GpioEdgeInput kButton(Chip::kPa14, Edge::Falling, Pull::Up);
constinit GpioEdgeInput button = kButton;
constinit GpioOut led(Chip::kPa26);
#endif
constexpr UartSerial::Config kSerialConfig{
    Chip::kUart0,
    Chip::kIrqUart0,
    static_cast<uint16_t>(reg::uart::baudDivisor64(kBusClockHz, config::kSlcanBaud)),
    Chip::kUart0TxPa8,
    DmaChannel{Chip::kDma, 0, Chip::kDmaTrigUart0Tx},
    Chip::kUart0RxPa9};
constinit UartSerial::RxBuffer serialReceived;  // zero: in .bss
constinit UartSerial serial(kSerialConfig, &serialReceived);
constinit Mspm0System system(Chip::kCpuss);
#if BSP_DEEP_IDLE
// The falling-edge wake inputs (all on GPIOA) that must read high before STANDBY1 (GPIO_ERR_01,
// power_policy.cpp).
constexpr uint32_t kWakePins = Chip::kPa15.mask() | (BMS_BOARD_LED_BUTTON ? Chip::kPa14.mask() : 0U);
static_assert(Chip::kPa15.port == 0 && Chip::kPa14.port == 0);
constexpr StandbyIdle::Config kIdleConfig{Chip::kTimg1, Chip::kIrqTimg1,        Chip::kI2c0,
                                          Chip::kUart0, Chip::kPa15.portBase(), kWakePins};
constinit StandbyIdle power(clock, kIdleConfig);
#endif

// The L1306 has one GPIO port, GPIOA: INT_GROUP1 needs no port look-up (GROUP1_IRQHandler below).
#if BMS_BOARD_LED_BUTTON
GpioEdgeInput* const kEdgeInputs[] = {&alert, &button};
constinit Board instance{clock, watchdog, i2c, alert, serial, system, button, led};
#else
GpioEdgeInput* const kEdgeInputs[] = {&alert};
constinit Board instance{clock, watchdog, i2c, alert, serial, system};
#endif

}  // namespace

Board& board() {
  return instance;
}

void bringUp() {
  system.capture();  // RSTCAUSE clears when read: first of all
  // The LaunchPad's ROSC resistor on PA2 lets the SYSOSC run in FCL mode (README "Clocks"; its fitting on the
  // LP-MSPM0L1306 is an open question there: pass 0 for a board without it).
  initSysosc(false, reg::sysctl::kFclKey | reg::sysctl::kFclSetUseFcl);
  powerGpioPort(kGpioaBase);
  TimgClock::start(kClockConfig);
#if BSP_DEEP_IDLE
  StandbyIdle::init(kIdleConfig);
  instance.power = &power;
#endif
  i2c.init();
  kAlert.init();
  UartSerial::init(kSerialConfig);
#if BMS_BOARD_LED_BUTTON
  led.init(false);
  kButton.init();
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
  bsp::mspm0::onPortInterrupt(image::Chip::kCpuss, bsp::mspm0::kGpioaBase, image::kEdgeInputs);
}
}
