// SYSCTL registers (SYSCTL_BASE 0x400AF000 on both parts). Source: mspm0*.tsv rows "SYSCTL.SOCLOCK.*" and
// "SYSCTL_*" (MSPM0 TRM SLAU846A section 2); reset levels from SLAU846A 2.4 (RESETLEVEL 0 is a software
// SYSRST: peripherals reset, SRAM kept; 1 is BOOTRST, which power-cycles SRAM).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::sysctl {

inline constexpr uintptr_t kBase = 0x400AF000;

struct Clocks {
  Reg sysosccfg;    // 0x1100
  Reg mclkcfg;      // 0x1104
  Reg hsclken;      // 0x1108 (G350x): HFXTEN bit 0
  Reg hsclkcfg;     // 0x110C (G350x)
  Reg hfclkclkcfg;  // 0x1110 (G350x)
  Reg reserved_[(0x1138 - 0x1114) / 4];
  Reg genclkcfg;  // 0x1138
};
inline constexpr uintptr_t kClocksOffset = 0x1100;
static_assert(kClocksOffset + offsetof(Clocks, hfclkclkcfg) == 0x1110);
static_assert(kClocksOffset + offsetof(Clocks, genclkcfg) == 0x1138);

struct Reset {
  Reg resetlevel;  // 0x1300
  Reg resetcmd;    // 0x1304
};

inline Clocks& clocks() {
  return mmio::block<Clocks>(kBase + kClocksOffset);
}
inline Reg& clkstatus() {
  return mmio::block<Reg>(kBase + 0x1204);
}
inline Reset& reset() {
  return mmio::block<Reset>(kBase + 0x1300);
}
// RSTCAUSE 0x1220: ID 4:0, the last reset's cause, a read-to-clear field (hw_sysctl_mspm0l11xx_l13xx.h and
// hw_sysctl_mspm0g1x0x_g3x0x.h SYSCTL_RSTCAUSE_ID: "read-to-clear"; 0 = no reset since the last read).
inline Reg& rstcause() {
  return mmio::block<Reg>(kBase + 0x1220);
}
inline constexpr uint32_t kRstcauseIdMask = 0x1F;

inline constexpr uint32_t kSysoscFreqMask = 0x3;  // FREQ 1:0, 0 = base (32 MHz)
inline constexpr uint32_t kMclkMdivMask = 0xF;    // MDIV 3:0, 0 = /1
inline constexpr uint32_t kMclkUdivMask = 0x30;   // UDIV 5:4 (G350x), 0 = ULPCLK not divided

// HFCLKCLKCFG: HFXTTIME 7:0 in 64 us units, HFXTRSEL 13:12 (3 = 32..48 MHz), HFCLKFLTCHK bit 28.
inline constexpr uint32_t kHfxtRange32To48 = 0x3000;
inline constexpr uint32_t kHfclkStartupCheck = 1U << 28;
inline constexpr uint32_t kHfxtEnable = 1U << 0;
inline constexpr uint32_t kCanClkSrcSysPll = 1U << 8;  // GENCLKCFG.CANCLKSRC: 0 = HFCLK
inline constexpr uint32_t kClkStatusHfclkGood = 1U << 8;

inline constexpr uint32_t kResetLevelSysrst = 0;
inline constexpr uint32_t kResetLevelBootloaderEntry = 2;  // RESETLEVEL_LEVEL_BOOTLOADERENTRY (SLAU887 3.2.2)
inline constexpr uint32_t kResetCmdGo = 0xE4000001;        // KEY 0xE4 | GO

}  // namespace bsp::mspm0::reg::sysctl
