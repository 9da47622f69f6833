#include "timg_one_shot.hpp"

#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"

namespace bsp::mspm0 {

namespace timg = reg::timg;

void TimgOneShot::init() {
  const uintptr_t base = config_.base;
  timg::powerUpClock(base, config_.prescaler);  // 1 MHz
  reg::EventBlock& events = reg::cpuInt(base);
  events.iclr.write(0xFFFFFFFF);
  events.imask.write(timg::kIntZero);
  nvic::enable(config_.irq);
}

void TimgOneShot::load(uint32_t microseconds) {
  // The 16-bit counter runs at most 0xFFFF ticks: the rest is left for onInterrupt() to load.
  const uint32_t chunk = microseconds > 0xFFFF ? 0xFFFF : microseconds;
  remaining_ = microseconds - chunk;
  timg::Counter& counter = timg::counter(config_.base);
  counter.ctrctl.write(0);
  counter.load.write(chunk);
  reg::cpuInt(config_.base).iclr.write(timg::kIntZero);
  // Down-count from LOAD (CVAE = load value) and stop at zero (REPEAT = 0): the zero event comes `chunk`
  // ticks after the enable.
  counter.ctrctl.write(timg::kCtrEnable | timg::kCtrCountDown | timg::kCtrStartAtLoad);
}

void TimgOneShot::start(uint32_t microseconds) {
  running_ = true;
  load(microseconds == 0 ? 1 : microseconds);
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
    load(remaining_);
    return false;
  }
  running_ = false;
  return true;
}

}  // namespace bsp::mspm0
