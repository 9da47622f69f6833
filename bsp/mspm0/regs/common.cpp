// Out-of-line helpers of the register layer: each is called from several drivers, and inlining them would
// repeat their key and address literals in every caller.
#include "regs/common.hpp"
#include "regs/cpuss.hpp"

namespace bsp::mspm0 {

void reg::resetAndPowerUp(Gprcm& gprcm) {
  gprcm.rstctl.write(kRstctlKeyAssert);
  gprcm.pwren.write(kPwrenKeyEnable);
  mmio::spin(4);  // 16 cycles
}

void nvic::enable(uint32_t irq) {
  regs().icpr.write(1U << irq);  // drop a pending state from before the driver was ready
  regs().iser.write(1U << irq);
}

}  // namespace bsp::mspm0
