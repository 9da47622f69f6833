// System clocks. Both chips run MCLK = CPUCLK = BUSCLK = ULPCLK = SYSOSC 32 MHz (the reset source; the TI
// examples use the same, tsv "CPUCLK_FREQ"). Flash wait states need no change: MCLKCFG.FLASHWAIT only
// applies when MCLK comes from HSCLK (sysctl MCLKCFG description).
//
// Contract
// - initSysosc(): thread mode at start-up; selects SYSOSC base frequency (32 MHz) and MCLK /1 (and on the
//   G3507 ULPCLK /1). Idempotent.
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

// Inline: one caller per image, whose constant argument leaves one write.
inline void initSysosc(bool hasUlpDivider) {
  reg::sysctl::Clocks& s = reg::sysctl::clocks();
  mmio::clearBits(s.sysosccfg, reg::sysctl::kSysoscFreqMask);
  mmio::clearBits(s.mclkcfg, reg::sysctl::kMclkMdivMask | (hasUlpDivider ? reg::sysctl::kMclkUdivMask : 0));
}
fw::Status startHfxt(const Pin& hfxin, const Pin& hfxout);

}  // namespace bsp::mspm0
