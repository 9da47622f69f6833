#include "timg_one_shot.hpp"

#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"

namespace bsp::mspm0 {

namespace timg = reg::timg;

void TimgOneShot::init() {
  const uintptr_t base = config_.base;
  reg::resetAndPowerUp(reg::gprcm(base));
  timg::Clock& clock = timg::clock(base);
  clock.clksel.write(timg::kClkselBusclk);
  clock.clkdiv.write(0);
  timg::Common& common = timg::common(base);
  common.cps.write(config_.prescaler);  // 1 MHz
  common.cclkctl.write(timg::kClockEnable);
  reg::EventBlock& events = reg::cpuInt(base);
  events.iclr.write(0xFFFFFFFF);
  events.imask.write(timg::kIntZero);
  nvic::enable(config_.irq);
}

void TimgOneShot::load(uint32_t chunk) {
  timg::Counter& counter = timg::counter(config_.base);
  counter.ctrctl.write(0);
  counter.load.write(chunk);
  reg::cpuInt(config_.base).iclr.write(timg::kIntZero);
  // Down-count from LOAD (CVAE = load value) and stop at zero (REPEAT = 0): the zero event comes `chunk`
  // ticks after the enable.
  counter.ctrctl.write(timg::kCtrEnable | timg::kCtrCountDown | timg::kCtrStartAtLoad);
}

void TimgOneShot::start(uint32_t microseconds) {
  if (microseconds == 0) microseconds = 1;
  const uint32_t chunk = microseconds > 0xFFFF ? 0xFFFF : microseconds;
  remaining_ = microseconds - chunk;
  running_ = true;
  load(chunk);
}

void TimgOneShot::stop() {
  running_ = false;
  timg::counter(config_.base).ctrctl.write(0);
  reg::cpuInt(config_.base).iclr.write(timg::kIntZero);
}

bool TimgOneShot::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  if ((pending & timg::kIntZero) == 0 || !running_) return false;
  if (remaining_ != 0) {
    const uint32_t chunk = remaining_ > 0xFFFF ? 0xFFFF : remaining_;
    remaining_ -= chunk;
    load(chunk);
    return false;
  }
  running_ = false;
  return true;
}

}  // namespace bsp::mspm0
