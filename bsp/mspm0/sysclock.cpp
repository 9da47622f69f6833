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
  // HFXTTIME 10 x 64 us = 640 us (TI example "startup 10"), range 32-48 MHz, start-up monitor on.
  s.hfclkclkcfg.write(sysctl::kHfclkStartupCheck | sysctl::kHfxtRange32To48 | 10U);
  mmio::setBits(s.hsclken, sysctl::kHfxtEnable);
  mmio::clearBits(s.genclkcfg, sysctl::kCanClkSrcSysPll);  // CANCLK = HFCLK
  for (uint32_t i = 0; i < 500; ++i) {
    if (sysctl::clkstatus().read() & sysctl::kClkStatusHfclkGood) return fw::Status::Ok;
    mmio::spin(80);  // ~10 us
  }
  return fw::Status::Timeout;
}

}  // namespace bsp::mspm0
