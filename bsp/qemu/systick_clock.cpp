#include "systick_clock.hpp"

#include "hal/irq.hpp"
#include "scs.hpp"

namespace bsp::qemu {

using bsp::scs::reg;

SysTickClock& sysTickClock() {
  static SysTickClock clock;
  return clock;
}

void SysTickClock::start(uint32_t periodUs) {
  periodUs_ = periodUs;
  reload_ = periodUs * (kCpuHz / 1000000) - 1;
  reg(scs::kSystCsr) = 0;
  reg(scs::kSystRvr) = reload_;
  reg(scs::kSystCvr) = 0;
  reg(scs::kSystCsr) = 0x7;  // CLKSOURCE = CPU clock, TICKINT, ENABLE
}

void SysTickClock::stop() {
  reg(scs::kSystCsr) = 0;
}

void SysTickClock::onTick() {
  ticks_ = ticks_ + 1;
  wakeFired();  // the tick is this clock's only wake-up: a timer may now be due
  fw::port::resumeOnExit();
  if (hook_ != nullptr) hook_();
}

fw::Instant SysTickClock::doNow() const {
  fw::hal::CriticalSection cs;
  uint32_t ticks = ticks_;
  uint32_t count = reg(scs::kSystCvr);
  if ((reg(scs::kScbIcsr) & scs::kIcsrPendStSet) != 0) {
    // The counter wrapped but the handler has not run yet (we are masked): count that tick here, and
    // re-read the counter so it belongs to the new period.
    count = reg(scs::kSystCvr);
    ++ticks;
  }
  const uint32_t sub = (reload_ - count) / (kCpuHz / 1000000);
  return fw::Instant{ticks * periodUs_ + sub};
}

}  // namespace bsp::qemu

extern "C" void SysTick_Handler() {
  bsp::qemu::sysTickClock().onTick();
}
