// System clocks. Both chips run MCLK = CPUCLK = BUSCLK = ULPCLK = SYSOSC 32 MHz (the reset source; the TI
// examples use the same, tsv "CPUCLK_FREQ"). Flash wait states need no change: MCLKCFG.FLASHWAIT only
// applies when MCLK comes from HSCLK (sysctl MCLKCFG description).
//
// Contract
// - initSysosc(hasUlpDivider, fclCommand): thread mode at start-up; selects SYSOSC base frequency (32 MHz),
//   then, with a non-zero `fclCommand` (reg::sysctl::kFclKey | kFclSetUseFcl [| kFclSetUseExternalResistor on
//   the MSPM0G]), turns the SYSOSC frequency correction loop on with the board's ROSC resistor, in TI's
//   order (SysConfig SYSCTL.Board.c.xdt: DL_SYSCTL_setSYSOSCFreq, then DL_SYSCTL_enableSYSOSCFCL...), and
//   sets MCLK /1 (and on the G3507 ULPCLK /1). The FCL is locked on until the next BOOTRST, so after a
//   SYSRST the write repeats what is already set. Idempotent.
//   Accuracy of the 32 MHz SYSOSC (data sheets SLASEX6B / SLASEX0D, SYSOSC table, -40..125 C): -2.6..+1.8 %
//   without the FCL; -1.1..+1.7 % with it and a 0.1 %, 25 ppm/C ROSC resistor (-1.1..+1.2 % up to 85 C);
//   README "Clocks".
// - startHfxt(hfxin, hfxout): G3507 only. Hands PA5/PA6 to the crystal oscillator, stops the HFXT in case a
//   software reset left it running, configures and starts it at 40 MHz (range 32-48 MHz, 640 us start-up
//   time, start-up monitor on, in the order of TI's example), selects HFCLK as CANCLK, and waits (bounded,
//   ~5 ms) for HFCLKGOOD. Ok or Timeout (no crystal, or a broken one).
#pragma once

#include <cstdint>

#include "core/status.hpp"
#include "mmio.hpp"
#include "pin.hpp"
#include "regs/sysctl.hpp"

namespace bsp::mspm0 {

inline constexpr uint32_t kBusClockHz = 32000000;

inline void initSysosc(bool hasUlpDivider, uint32_t fclCommand) {
  reg::sysctl::Clocks& s = reg::sysctl::clocks();
  mmio::clearBits(s.sysosccfg, reg::sysctl::kSysoscFreqMask);
  if (fclCommand != 0) reg::sysctl::sysoscFclCtl().write(fclCommand);
  mmio::clearBits(s.mclkcfg, reg::sysctl::kMclkMdivMask | (hasUlpDivider ? reg::sysctl::kMclkUdivMask : 0));
}
fw::Status startHfxt(const Pin& hfxin, const Pin& hfxout);

}  // namespace bsp::mspm0
