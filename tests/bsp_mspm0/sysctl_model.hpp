// SysctlModel: the MSPM0G3507 high-frequency crystal oscillator (HFXT) controls of SYSCTL in the register
// model. Offsets: mspm0g3507.tsv "SYSCTL.SOCLOCK.*" rows (HSCLKEN 0x1108, HFCLKCLKCFG 0x1110, CLKSTATUS
// 0x1204 at SYSCTL_BASE 0x400AF000); fields: its "SYSCTL_HSCLKEN_*", "SYSCTL_HFCLKCLKCFG_*",
// "SYSCTL_CLKSTATUS_*" rows.
//
// Rules (TI source next to each)
// - The HFXT's range and start-up time (HFCLKCLKCFG.HFXTRSEL, HFXTTIME) change only while HSCLKEN.HFXTEN is
//   clear: TI's DL_SYSCTL_setHFCLKSourceHFXTParams disables the HFXT before it sets them, because some
//   crystal settings survive the lower reset levels (its comment); the images' fault path is such a reset (a
//   software SYSRST). A change with HFXTEN set is flagged. (TI enables the start-up monitor, HFCLKFLTCHK,
//   after HFXTEN.)
// - CLKSTATUS.HFCLKGOOD reads 1 from the third CLKSTATUS read after HFXTEN is set with HFXTRSEL = 32-48 MHz
//   (the LaunchPad's 40 MHz crystal, tsv example "HFXT"); never with crystalMissing().
#pragma once

#include <cstdint>

namespace bsp::mspm0::test {

class SysctlModel {
 public:
  void attach();
  // State after a software SYSRST that kept the oscillator running (HFXTEN still set) with the settings of
  // an earlier configuration (range 16-32 MHz, longest start-up time).
  void hfxtLeftRunning();
  void crystalMissing() { crystalMissing_ = true; }

 private:
  bool crystalMissing_ = false;
  uint32_t readsSinceEnable_ = 0;
  uint32_t config_ = 0;  // HFCLKCLKCFG as last written
};

}  // namespace bsp::mspm0::test
