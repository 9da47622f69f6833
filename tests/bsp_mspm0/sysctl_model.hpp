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
// - SYSOSCFCLCTL (0x1310): a write without KEY 0x2A in 31:24 is ignored by the part and flagged ("The key
//   value of 2Ah (42) must be written to KEY together with SETUSEFCL to enable the FCL", hw_sysctl_*.h);
//   with the key and SETUSEFCL the FCL is on and CLKSTATUS.FCLMODE (bit 24) reads 1; SETUSEEXRES (bit 1)
//   on a part without it (the L11xx/L13xx: hw_sysctl_mspm0l11xx_l13xx.h has no such field) is flagged. The
//   FCL comes on only after SYSOSCCFG.FREQ selected the base frequency (TI's SysConfig order,
//   SYSCTL.Board.c.xdt: DL_SYSCTL_setSYSOSCFreq then DL_SYSCTL_enableSYSOSCFCL): an FCL write before any
//   SYSOSCCFG write is flagged.
// - RSTCAUSE (0x1220) holds the cause set by resetCause(); a read returns it and clears it: "The contents of
//   the reset cause register are always cleared upon a read, and return zero after being read if no reset
//   has occurred after the read" (SLAU846B / SLAU847D, text above
//   Table 2-12 / 2-9).
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
  // The part has no SYSOSCFCLCTL.SETUSEEXRES (MSPM0L11xx/L13xx).
  void withoutExternalResistorSelect() { noExResSelect_ = true; }
  // The reset that preceded this run (RSTCAUSE.ID), readable once.
  void resetCause(uint32_t id);
  bool fclOn() const { return fclOn_; }

 private:
  bool crystalMissing_ = false;
  bool noExResSelect_ = false;
  bool fclOn_ = false;
  uint32_t cause_ = 0;
  uint32_t readsSinceEnable_ = 0;
  uint32_t config_ = 0;  // HFCLKCLKCFG as last written
};

}  // namespace bsp::mspm0::test
