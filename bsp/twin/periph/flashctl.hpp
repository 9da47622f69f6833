// Flashctl: the MSPM0 flash controller (FLASHCTL, base 0x400CD000 on both parts, tsv "base" rows) as TI
// documents it, for the commands the firmware's FlashctlStorage (bsp/mspm0/flashctl.hpp) issues.
//
// Registers (hw_flashctl.h FLASHCTL_GEN_Regs): CMDEXEC 0x1100, CMDTYPE 0x1104 (COMMAND 2:0, SIZE 6:4),
// CMDCTL 0x1108, CMDADDR 0x1120, CMDBYTEN 0x1124, CMDDATA0/1 0x1130/0x1134, CMDWEPROTA 0x11D0 (bit n: sector
// n), CMDWEPROTB 0x11D4 (bit n: sectors 32 + 8n .. 39 + 8n), CMDWEPROTNM 0x1210, STATCMD 0x13D0 (CMDDONE 0,
// CMDPASS 1, CMDINPROGRESS 2, FAILWEPROT 4, FAILVERIFY 5, FAILILLADDR 6, FAILMODE 7, FAILINVDATA 8,
// FAILMISC 12). Any other register, or a command other than PROGRAM ONEWORD / ERASE SECTOR, stops the run
// (not modelled). FLASHCTL has no GPRCM block (hw_flashctl.h FLASHCTL_GEN_Regs holds nothing below 0x1020:
// no PWREN to set), so the model is a plain Device, always powered.
//
// Behaviour
// - Protection: every sector is protected after reset and again after every command ("the flash controller
//   re-protects all memory after every command": TRM SLAU846A/SLAU847 FLASHCTL, dl_flashctl.h
//   DL_FlashCTL_unprotectSector before each command in TI's flashctl examples). A command on a protected
//   sector ends with STATCMD = CMDDONE | FAILWEPROT and does nothing (hw_flashctl.h STATCMD.FAILWEPROT).
// - Stall: a program or erase takes the data sheet's typical time (word 50 us, sector erase 4 ms: MSPM0L110x
//   SLASEX5C / MSPM0G310x-Q1 7.7). While it runs the CPU fetches no instruction from flash: the core waits
//   (Machine::stallFlashUntil) until it ends, as the one bank stalls every read request, data loads too
//   (SLAU846A NVM chapter, flash banks; SLAAE56A flash memory organization). Code in SRAM runs on until it
//   loads from flash (a literal, a constant table): that instruction waits for the end. (DMA reads of the
//   flash are not stalled in the model: no image's DMA reads flash.)
// - ECC (G3507): the 8 ECC bits are computed by the hardware when CMDBYTEN enables the ECC byte (bit 8) and
//   CMDCTL.ECCGENOVR is clear (hw_flashctl.h); a program without the ECC byte, or with the override, stops
//   (not modelled: the word would read back with an ECC error, SLAU846A program section).
// - Power cut: cutPower() ends a program or erase in progress as a power failure would, leaving the word
//   half programmed (its first bytes, in proportion to the time elapsed) or the sector half erased (its
//   first bytes); TI says nothing about the pattern a cut leaves, so this is the twin's choice, and the
//   firmware must treat any content as possible (hal/flash.hpp). The caller then resets the machine (POR):
//   the flash keeps its content.
// Rules (rules.hpp), each a stop:
//   FLASH-PROTECTED   a command on a sector whose protection bit was not cleared before CMDEXEC
//   FLASH-UNERASED    a program into a word that is not erased (G3507: the ECC of the word would no longer
//                     match, SLAU846A program section; L1306: the safe side, hal/flash.hpp's contract)
//   FLASH-REGION      a command addressed to NONMAIN (0x41C00000..) or to the sectors of the loaded image
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "address_map.hpp"
#include "timeline.hpp"

namespace twin {

class Machine;

class Flashctl final : public Device {
 public:
  static constexpr uint32_t kBase = 0x400CD000;
  static constexpr uint32_t kSize = 0x2000;
  static constexpr uint32_t kSectorBytes = 1024;
  static constexpr uint32_t kProgramUs = 50;  // typical word program (data sheet 7.7)
  static constexpr uint32_t kEraseUs = 4000;  // typical sector erase, <= 2 k cycles (data sheet 7.7)

  enum class Op : uint8_t { None, Program, Erase };

  Flashctl(Machine& machine, bool ecc);
  const char* name() const override { return "FLASHCTL"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;

  void systemReset();
  // Flash below `end` holds the image: a command there breaks FLASH-REGION.
  void setImageEnd(uint32_t end) { imageEnd_ = end; }
  // The operation running now, and how many program/erase commands have started since construction.
  Op busy() const { return op_; }
  uint64_t commandsStarted() const { return started_; }
  // Power fails now: an operation in progress is left half done (see above) and abandoned.
  void cutPower();
  // What cutPower() now would leave in `flash` (the machine's flash, or a copy of it, to know a cut's result
  // without making it); nothing else changes.
  void leaveCut(std::vector<uint8_t>& flash) const;

 private:
  void execute();
  void finish();
  void fail(uint32_t why);
  bool sectorProtected(uint32_t sector) const;

  Machine& machine_;
  bool ecc_;
  uint32_t cmdtype_ = 0, cmdctl_ = 0, cmdaddr_ = 0, cmdbyten_ = 0, data0_ = 0, data1_ = 0;
  uint32_t weprotA_ = ~0U, weprotB_ = ~0U, weprotNm_ = ~0U;
  uint32_t statcmd_ = 0;
  uint32_t imageEnd_ = 0;
  Op op_ = Op::None;
  uint64_t opStart_ = 0;
  uint64_t started_ = 0;
  TimedEvent done_;
};

}  // namespace twin
