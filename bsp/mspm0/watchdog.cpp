#include "watchdog.hpp"

#include "core/assert.hpp"
#include "mmio.hpp"
#include "regs/wwdt.hpp"

FW_MODULE(fw::Module::Bsp);

namespace bsp::mspm0 {

namespace wwdt = reg::wwdt;

void WindowWatchdog::start() {
  reg::resetAndPowerUp(reg::gprcm(base_));
  // KEY | PER = 2^15 | CLKDIV = 0 (/1) | WINDOW0 = 0 % | MODE = watchdog: 32768 / 32768 Hz = 1.0 s.
  wwdt::control(base_).ctl0.write(wwdt::kCtl0Key | (wwdt::kPer2Pow15 << wwdt::kPerShift));
}

void WindowWatchdog::doFeed() {
  FW_ASSERT(stackGuardIntact());  // the stack grew into its guard words: reset with a record
  wwdt::control(base_).cntrst.write(wwdt::kRestart);
}

}  // namespace bsp::mspm0
