#include "sysclock.hpp"

#include "mmio.hpp"
#include "regs/gpio.hpp"
#include "regs/sysctl.hpp"

namespace bsp::mspm0 {

namespace sysctl = reg::sysctl;

fw::Status startHfxt(const Pin& hfxin, const Pin& hfxout) {
  sysctl::Clocks& s = sysctl::clocks();
  // PINCM = 0: no digital function connected, the pads belong to the oscillator.
  reg::iomux::pincm(hfxin.pincm).write(0);
  reg::iomux::pincm(hfxout.pincm).write(0);
  // TI's order (DL_SYSCTL_setHFCLKSourceHFXTParams): the HFXT off first, since some of its settings survive
  // the lower reset levels (the software SYSRST of fw::onFault is one); then range 32-48 MHz and HFXTTIME
  // 10 x 64 us = 640 us (TI example "startup 10"); the HFXT on; then the start-up monitor.
  mmio::clearBits(s.hsclken, sysctl::kHfxtEnable);
  s.hfclkclkcfg.write(sysctl::kHfxtRange32To48 | 10U);
  mmio::setBits(s.hsclken, sysctl::kHfxtEnable);
  mmio::setBits(s.hfclkclkcfg, sysctl::kHfclkStartupCheck);
  mmio::clearBits(s.genclkcfg, sysctl::kCanClkSrcSysPll);  // CANCLK = HFCLK
  for (uint32_t i = 0; i < 500; ++i) {
    if (sysctl::clkstatus().read() & sysctl::kClkStatusHfclkGood) return fw::Status::Ok;
    mmio::spin(80);  // ~10 us
  }
  return fw::Status::Timeout;
}

}  // namespace bsp::mspm0
