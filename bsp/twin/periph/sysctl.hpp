// Sysctl: the SYSCTL clock and reset registers the images use (SYSCTL_BASE 0x400AF000 on both parts;
// offsets and fields from mspm0-sdk hw_sysctl_mspm0g1x0x_g3x0x.h / hw_sysctl_mspm0l11xx_l13xx.h, behaviour
// from SLAU846B/SLAU847D chapter 2 "PMCU").
//
// - SYSOSCCFG.FREQ and MCLKCFG: the twin runs the CPU at SYSOSC's 32 MHz base frequency, MCLK and ULPCLK
//   undivided. A write that selects anything else (another SYSOSC frequency, MDIV, UDIV, HSCLK or LFCLK as
//   MCLK) stops the run: the timeline would be wrong, not merely slow.
// - HFXT (MSPM0G only: HSCLKEN, HFCLKCLKCFG, GENCLKCFG.CANCLKSRC): HSCLKEN.HFXTEN starts the 40 MHz crystal
//   of the LP-MSPM0G3507 (tsv "HFXT" example row); with the start-up monitor on (HFCLKFLTCHK),
//   CLKSTATUS.HFCLKGOOD is set HFXTTIME x 64 us later ("HFXTTIME specifies the HFXT startup time in 64us
//   resolution. If the HFCLK startup monitor is enabled, HFXT will be checked after this time expires",
//   hw_sysctl HFCLKCLKCFG). The MCAN model asks canClockRunning().
// - RESETLEVEL/RESETCMD: KEY 0xE4 with GO issues the reset RESETLEVEL names (0 SYSRST "CPU plus peripherals
//   only", 1 BOOTRST, 3 POR; hw_sysctl RESETLEVEL_LEVEL_*).
// - RSTCAUSE (0x1220): ID 4:0, the last reset's cause, "a read-to-clear field" (hw_sysctl SYSCTL_RSTCAUSE_ID;
//   0 NORST once read). Software resets give SYSSW 0x1B, BOOTSW 0x0D, PORSW 0x03 (the RESETCMD levels 0, 1,
//   3); the twin's other BOOTRST source, the WWDT, SYSWWDT0 0x0E; its other SYSRST source (AIRCR.SYSRESETREQ)
//   CPUSW 0x1D; a power-up BORSUPPLY 0x04 (the supply rising through BOR0). TI's documents do not say which
//   ID a cold power-up reads (README, open questions).
// Registers the images do not use are not modelled: an access stops the run.
#pragma once

#include <cstdint>

#include "address_map.hpp"
#include "machine.hpp"

namespace twin {

class Sysctl final : public Device {
 public:
  static constexpr uint32_t kBase = 0x400AF000;
  static constexpr uint32_t kSize = 0x2000;

  Sysctl(Machine& machine, bool hasHfxt);
  const char* name() const override { return "SYSCTL"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;

  bool canClockRunning() const;

 private:
  void reset(ResetKind kind);

  Machine& machine_;
  bool hasHfxt_;
  uint32_t sysosccfg_ = 0, mclkcfg_ = 0, hsclken_ = 0, hsclkcfg_ = 0, hfclkclkcfg_ = 0, genclkcfg_ = 0;
  uint32_t resetLevel_ = 0;
  uint32_t resetCause_ = 0;
  int softwareLevel_ = -1;  // the RESETLEVEL of a RESETCMD reset under way
  uint64_t hfxtGoodAt_ = UINT64_MAX;
};

}  // namespace twin
