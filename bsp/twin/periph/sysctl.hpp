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
//   hw_sysctl HFCLKCLKCFG). The MCAN model asks canClockRunning(). On a board without a crystal
//   (removeCrystal(): bms-sim --no-crystal) the monitor sets CLKSTATUS.HFCLKOFF instead at that time and
//   HFCLKGOOD never comes ("If the HFXT did not start within the specified startup time, the HFCLKOFF bit is
//   set, indicating that the HFXT was dead at startup", SLAU846A 2 HFXT startup monitor; hw_sysctl
//   CLKSTATUS.HFCLKOFF bit 13); a CPU still polling CLKSTATUS 20 ms after that stops the run (rules.hpp
//   HFXT-WAIT-UNBOUNDED).
// - RESETLEVEL/RESETCMD: KEY 0xE4 with GO issues the reset RESETLEVEL names (0 SYSRST "CPU plus peripherals
//   only", 1 BOOTRST, 2 "SYSRST and enter the bootloader", 3 POR, 4 "SYSRST and exit the bootloader";
//   hw_sysctl RESETLEVEL_LEVEL_*, the same values in mspm0-sdk dl_sysctl_mspm0{l11xx_l13xx,g1x0x_g3x0x}.h
//   DL_SYSCTL_RESET_BOOTLOADER_ENTRY/EXIT). Levels 2 and 4 leave their request for the boot code
//   (bsl/boot_code.hpp, takeBootRequest()), which the reset runs; 5..7 are undefined and stop the run. They
//   leave RSTCAUSE 0x1B / 0x0D / 0x11 (SYSBSLENTRY) / 0x03 / 0x10 (SYSBSLEXIT).
// - RSTCAUSE (0x1220): the lowest-level cause of the resets since the last read (Machine::takeResetCause:
//   power-on 0x01, WWDT0 violation 0x0E, the software resets above, AIRCR.SYSRESETREQ 0x1D), cleared by the
//   read ("The contents of the reset cause register are always cleared upon a read", text above SLAU846B
//   Table 2-12 / SLAU847D Table 2-9; IDs from hw_sysctl RSTCAUSE_ID_*, their levels from SLAU846B Table
//   2-12).
// - SYSOSCFCLCTL (0x1310): KEY 0x2A with SETUSEFCL turns the frequency correction loop on until the next
//   BOOTRST (CLKSTATUS.FCLMODE reads 1); without the key the write is ignored; SETUSEEXRES on the L1306
//   stops the run (no such field there). The FCL comes on only after SYSOSCCFG selected the frequency it
//   corrects: TI's SysConfig order (SYSCTL.Board.c.xdt: the SYSOSC frequency, then the FCL); TI gives no
//   behaviour for the other order, so the twin takes the safe side and an FCL turned on before any SYSOSCCFG
//   write since the reset stops the run.
// - The HFXT's range and start-up time (HFCLKCLKCFG.HFXTRSEL 13:12, HFXTTIME 7:0) change only while
//   HSCLKEN.HFXTEN is clear: TI's HFXT set-up turns the HFXT off before it sets them, because some crystal
//   settings survive the lower reset levels (mspm0-sdk dl_sysctl_mspm0g1x0x_g3x0x.c, HFXT parameters); the
//   images' fault path is such a reset (a software SYSRST). A change with HFXTEN set stops the run.
// - The crystal's range (rules.hpp WIRE-HFXT-RANGE): when HSCLKEN.HFXTEN starts the HFXT,
//   HFCLKCLKCFG.HFXTRSEL must name the range the board's crystal lies in (hw_sysctl HFXTRSEL: 0 4..8, 1
//   8..16, 2 16..32, 3 32..48 MHz; the LP-MSPM0G3507's 40 MHz crystal needs 3).
// - PMODECFG (0x1140) with SYSOSCCFG.USE4MHZSTOP/DISABLESTOP and MCLKCFG.STOPCLKSTBY select the mode
//   SCR.SLEEPDEEP enters (power_mode.hpp; the machine's residency and SLEEP-EVENT-LOST); SHUTDOWN stops
//   the run.
// Registers the images do not use are not modelled: an access stops the run.
#pragma once

#include <cstdint>
#include <string>

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
  // Why CANCLK cannot run (rules.hpp CLOCK-OFF): its source is off; "" when it is on or starting.
  std::string canClockProblem() const;
  void setHfxtCrystalHz(uint32_t hz) { crystalHz_ = hz; }
  // A board fault: no crystal on HFXIN/HFXOUT (or one that never oscillates). Until the next construction.
  void removeCrystal() { crystalFitted_ = false; }
  // The mode SCR.SLEEPDEEP enters now: PMODECFG.DSLEEP, SYSOSCCFG and MCLKCFG.STOPCLKSTBY (power_mode.hpp).
  PowerMode deepSleepMode() const;

  enum class BootRequest : uint8_t { None, EnterBootloader, ExitBootloader };
  // The bootloader request of the software reset in progress (RESETLEVEL 2 or 4), taken once.
  BootRequest takeBootRequest() {
    const BootRequest r = bootRequest_;
    bootRequest_ = BootRequest::None;
    return r;
  }

 private:
  void reset(ResetKind kind);

  Machine& machine_;
  bool hasHfxt_;
  uint32_t sysosccfg_ = 0, mclkcfg_ = 0, hsclken_ = 0, hsclkcfg_ = 0, hfclkclkcfg_ = 0, genclkcfg_ = 0;
  uint32_t resetLevel_ = 0, pmodecfg_ = 0;
  uint8_t shutdnStore_[4] = {};  // SHUTDNSTORE0..3, kept across resets (hw_sysctl: shutdown storage memory)
  BootRequest bootRequest_ = BootRequest::None;
  bool fclMode_ = false;
  bool sysoscFreqWritten_ = false;  // SYSOSCCFG written since the reset (the FCL's order)
  // Reads CLKSTATUS as the start-up monitor has it: HFCLKGOOD, or HFCLKOFF on a board without a crystal.
  uint32_t hfclkStatus();

  uint64_t hfxtGoodAt_ =
      UINT64_MAX;  // when the start-up monitor gives its verdict (HFXTTIME after the start)
  uint32_t crystalHz_ = 0;
  bool crystalFitted_ = true;
  uint64_t pollStart_ = 0, lastPoll_ = 0;  // the current run of CLKSTATUS reads (HFXT-WAIT-UNBOUNDED)
};

}  // namespace twin
