// Flash controller (FLASHCTL) registers, MSPM0L1306 and MSPM0G3507: FLASHCTL_BASE 0x400CD000 (tsv "base"
// rows). Offsets and fields from TI's hw_flashctl.h (FLASHCTL_GEN_Regs) and the same field masks as
// dl_flashctl.h uses them; the command sequence from the TRM FLASHCTL chapter (SLAU846A / SLAU847).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::flashctl {

struct Command {
  Reg cmdexec;  // 0x1100 VAL bit 0: execute the command set up in the other registers
  Reg cmdtype;  // 0x1104 COMMAND 2:0, SIZE 6:4
  Reg cmdctl;   // 0x1108 REGIONSEL 12:9 (used only with ADDRXLATEOVR), ECCGENOVR bit 17
  Reg unused[5];
  Reg cmdaddr;       // 0x1120 system address of the word / sector
  Reg cmdbyten;      // 0x1124 one enable bit per byte of the flash word; bit 8: the ECC byte
  Reg unused2;       // 0x1128
  Reg cmddataindex;  // 0x112C
  Reg cmddata0;      // 0x1130 data bits 31:0
  Reg cmddata1;      // 0x1134 data bits 63:32
};
inline constexpr uintptr_t kCommandOffset = 0x1100;
static_assert(kCommandOffset + offsetof(Command, cmdaddr) == 0x1120);
static_assert(kCommandOffset + offsetof(Command, cmddata1) == 0x1134);

struct Protect {
  Reg cmdweprota;  // 0x11D0 one bit per sector 0..31 of the bank, 1 = protected
  Reg cmdweprotb;  // 0x11D4 one bit per 8 sectors beyond
};
inline constexpr uintptr_t kProtectOffset = 0x11D0;

inline constexpr uintptr_t kStatcmdOffset = 0x13D0;  // STATCMD, read only

inline Command& command(uintptr_t base) {
  return mmio::block<Command>(base + kCommandOffset);
}
inline Protect& protect(uintptr_t base) {
  return mmio::block<Protect>(base + kProtectOffset);
}
inline const Reg& statcmd(uintptr_t base) {
  return mmio::block<Reg>(base + kStatcmdOffset);
}

inline constexpr uint32_t kExecute = 1;            // CMDEXEC.VAL
inline constexpr uint32_t kCommandProgram = 0x1;   // CMDTYPE.COMMAND PROGRAM
inline constexpr uint32_t kCommandErase = 0x2;     // CMDTYPE.COMMAND ERASE
inline constexpr uint32_t kSizeOneWord = 0x00;     // CMDTYPE.SIZE ONEWORD
inline constexpr uint32_t kSizeSector = 0x40;      // CMDTYPE.SIZE SECTOR
inline constexpr uint32_t kByteEnableData = 0xFF;  // CMDBYTEN: the 8 data bytes
// CMDBYTEN 0x1FF = "64-bit programming with ECC enabled", 0xFF = 64-bit without (dl_flashctl.h
// DL_FlashCTL_setCommandByteEnable; hw_flashctl.h CMDBYTEN: one bit per byte "including the ECC byte").
inline constexpr uint32_t kByteEnableEcc = 0x100;  // CMDBYTEN: the ECC byte (parts with ECC)
inline constexpr uint32_t kEccGenOverride = 1U
                                            << 17;  // CMDCTL.ECCGENOVR: left clear, the hardware computes ECC

// STATCMD fields (hw_flashctl.h FLASHCTL_STATCMD_*).
inline constexpr uint32_t kStatDone = 1U << 0;
inline constexpr uint32_t kStatPass = 1U << 1;
inline constexpr uint32_t kStatInProgress = 1U << 2;
inline constexpr uint32_t kStatFailWeProt = 1U << 4;
inline constexpr uint32_t kStatFailVerify = 1U << 5;
inline constexpr uint32_t kStatFailIllAddr = 1U << 6;
inline constexpr uint32_t kStatFailMode = 1U << 7;
inline constexpr uint32_t kStatFailInvData = 1U << 8;
inline constexpr uint32_t kStatFailMisc = 1U << 12;

}  // namespace bsp::mspm0::reg::flashctl
