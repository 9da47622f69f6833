// Board instance and interrupt glue of the LP-MSPM0G3507 CAN images: every driver object is built at
// compile time (constinit) from the chip facts and the image's board_config.hpp. The monitor link (I2C0 or
// the BQ79616 UART) is the only part that differs between the images.
#include "board_g3507_can.hpp"
#include "can/bms.hpp"
#include "chip/mspm0g3507.hpp"
#include "gpio.hpp"
#include "mcan.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"
#include "sysclock.hpp"
#include "system.hpp"
#include "timg_clock.hpp"
#include "watchdog.hpp"
#if BMS_BOARD_MONITOR_ON_UART
#include "regs/uart.hpp"
#include "uart_link.hpp"
#else
#include "i2c.hpp"
#endif

extern "C" uint32_t __stack_limit__[];

namespace image {
namespace {

using Chip = bsp::mspm0::chip::Mspm0g3507;
using namespace bsp::mspm0;

#if BMS_BOARD_MONITOR_ON_UART
// The BQ79616 UART is a board setting (CMake BMS_BQ79616_UART): seed 001 wires UART0 PA10/PA11, TI's SDK
// example UART1 PA8/PA9.
#if defined(BMS_BQ79616_UART1) && BMS_BQ79616_UART1
#define BMS_BQ79616_UART_IRQ_HANDLER UART1_IRQHandler
constexpr bool kUart1 = true;
#else
#define BMS_BQ79616_UART_IRQ_HANDLER UART0_IRQHandler
constexpr bool kUart1 = false;
#endif
constinit UartLink monitorLink(
    {kUart1 ? Chip::kUart1 : Chip::kUart0, kUart1 ? Chip::kIrqUart1 : Chip::kIrqUart0,
     static_cast<uint16_t>(reg::uart::baudDivisor64(kBusClockHz, config::kBq79616Baud)), config::kBq79616Baud,
     kUart1 ? Chip::kUart1TxPa8 : Chip::kUart0TxPa10, kUart1 ? Chip::kUart1RxPa9 : Chip::kUart0RxPa11,
     DmaChannel{Chip::kDma, 0, kUart1 ? Chip::kDmaTrigUart1Rx : Chip::kDmaTrigUart0Rx},
     DmaChannel{Chip::kDma, 1, kUart1 ? Chip::kDmaTrigUart1Tx : Chip::kDmaTrigUart0Tx},
     TimgOneShot::Config{Chip::kTimg6, Chip::kIrqTimg6, reg::timg::prescalerFor1MHz(kBusClockHz)}});
#else
constexpr I2cTiming kI2cTiming = i2cTiming(kBusClockHz, config::kI2cBitRate, config::kI2cStretchLimitUs);
static_assert(kI2cTiming.valid, "no I2C clock divider gives this bit rate and stretch limit");
constinit I2cController monitorLink({Chip::kI2c0, Chip::kIrqI2c0, Chip::kI2c0SdaPa0, Chip::kI2c0SclPa1,
                                     config::kI2cBitRate, kI2cTiming});
#endif

constinit TimgClock clock({Chip::kTimg0, Chip::kIrqTimg0, reg::timg::prescalerFor1MHz(kBusClockHz)});
constinit WindowWatchdog watchdog(Chip::kWwdt0, __stack_limit__);
// The monitor's active-low signal on PB0, taken on its falling edge: the BQ76952 ALERT, which the images set
// open-drain, needs the internal pull-up (IOMUX PINCM.PIPU, bit 17; hw_iomux.h IOMUX_PINCM_PIPU); the
// BQ79616 nFAULT is driven by the device (TI's example reads it with no pull) and the pull-up does no harm.
constinit GpioEdgeInput monitorSignal(Chip::kPb0, Edge::Falling, Pull::Up);
#if BMS_BOARD_LED_BUTTON
constinit GpioEdgeInput button(Chip::kPb21, Edge::Falling, Pull::Up);
constinit GpioOut led(Chip::kPb22);
#endif
constinit GpioOut faultOut(Chip::kPb26);
constinit McanBus can({Chip::kCanfd0, Chip::kIrqCanfd0, Chip::kCanTxPa12, Chip::kCanRxPa13,
                       McanBus::kNbtp500k, fw::can::bms::kReceivedIds});
constinit Mspm0System system(Chip::kCpuss);

constexpr uintptr_t kGpioPorts[] = {kGpioaBase, kGpioaBase + kGpioPortStride};
#if BMS_BOARD_LED_BUTTON
GpioEdgeInput* const kEdgeInputs[] = {&monitorSignal, &button};
constinit Board instance{clock, watchdog, monitorLink,          monitorSignal, faultOut,
                         can,   system,   fw::Status::NotReady, button,        led};
#else
GpioEdgeInput* const kEdgeInputs[] = {&monitorSignal};
constinit Board instance{clock,    watchdog, monitorLink, monitorSignal,
                         faultOut, can,      system,      fw::Status::NotReady};
#endif
constinit GpioInterrupts gpioInterrupts(Chip::kCpuss, kGpioPorts, kEdgeInputs);

}  // namespace

Board& board() {
  return instance;
}

void bringUp() {
  system.capture();  // RSTCAUSE clears when read: first of all
  // The LP-MSPM0G3507 fits R8, 100 kOhm 0.1 %, from ROSC (PA2) to ground (SLAU873D 2.7 and its schematic):
  // the SYSOSC runs in FCL mode on the external resistor (README "Clocks").
  initSysosc(true,
             reg::sysctl::kFclKey | reg::sysctl::kFclSetUseFcl | reg::sysctl::kFclSetUseExternalResistor);
  powerGpioPort(kGpioaBase);
  powerGpioPort(kGpioaBase + kGpioPortStride);
  faultOut.init(true);  // asserted until the application has measured the pack and released it
#if BMS_BOARD_LED_BUTTON
  led.init(false);
  button.init();
#endif
  clock.start();
  monitorLink.init();
  monitorSignal.init();
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
#if BMS_BOARD_MONITOR_ON_UART
void TIMG6_IRQHandler() {
  image::monitorLink.onTimerInterrupt();
}
void BMS_BQ79616_UART_IRQ_HANDLER() {
  image::monitorLink.onUartInterrupt();
}
#else
void I2C0_IRQHandler() {
  image::monitorLink.onInterrupt();
}
#endif
void CANFD0_IRQHandler() {
  image::can.onInterrupt();
}
void GROUP1_IRQHandler() {
  image::gpioInterrupts.onInterrupt();
}
}
