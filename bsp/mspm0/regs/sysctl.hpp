// SYSCTL registers (SYSCTL_BASE 0x400AF000 on both parts). Source: mspm0*.tsv rows "SYSCTL.SOCLOCK.*" and
// "SYSCTL_*" (MSPM0 TRM SLAU846A section 2); reset levels from SLAU846B Table 2-12 / SLAU847D Table 2-9
// (RESETLEVEL 0 is a software SYSRST: CPU and peripherals reset, SRAM kept; 1 is a software BOOTRST, which
// also resets SRAM).
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
inline Reg& sysoscFclCtl() {
  return mmio::block<Reg>(kBase + 0x1310);
}
// PMODECFG (SOCLOCK 0x1140, hw_sysctl_mspm0l11xx_l13xx.h and _g1x0x_g3x0x.h): the mode SCR.SLEEPDEEP enters.
inline Reg& pmodecfg() {
  return mmio::block<Reg>(kBase + 0x1140);
}
inline Reg& rstcause() {
  return mmio::block<Reg>(kBase + 0x1220);
}

inline constexpr uint32_t kSysoscFreqMask = 0x3;  // FREQ 1:0, 0 = base (32 MHz)
inline constexpr uint32_t kMclkMdivMask = 0xF;    // MDIV 3:0, 0 = /1
inline constexpr uint32_t kMclkUdivMask = 0x30;   // UDIV 5:4 (G350x), 0 = ULPCLK not divided
// MCLKCFG.STOPCLKSTBY (bit 21): in STANDBY only TIMG0/TIMG1 (and the RTC) keep ULPCLK/LFCLK: STANDBY1; clear,
// every PD0 peripheral keeps LFCLK: STANDBY0 (hw_sysctl_mspm0l11xx_l13xx.h MCLKCFG_STOPCLKSTBY_ENABLE
// 0x00200000; TI's DL_SYSCTL_setPowerPolicySTANDBY1 sets it, ..STANDBY0 clears it).
inline constexpr uint32_t kMclkStopClkStandby = 1U << 21;
// PMODECFG.DSLEEP 1:0: 0 STOP, 1 STANDBY, 2 SHUTDOWN (hw_sysctl PMODECFG_DSLEEP_STANDBY 0x1).
inline constexpr uint32_t kPmodeStandby = 1;

// HFCLKCLKCFG: HFXTTIME 7:0 in 64 us units, HFXTRSEL 13:12 (3 = 32..48 MHz), HFCLKFLTCHK bit 28.
inline constexpr uint32_t kHfxtRange32To48 = 0x3000;
inline constexpr uint32_t kHfclkStartupCheck = 1U << 28;
inline constexpr uint32_t kHfxtEnable = 1U << 0;
inline constexpr uint32_t kCanClkSrcSysPll = 1U << 8;  // GENCLKCFG.CANCLKSRC: 0 = HFCLK
inline constexpr uint32_t kClkStatusHfclkGood = 1U << 8;

// SYSOSCFCLCTL (hw_sysctl_*.h): KEY 0x2A in 31:24 with SETUSEFCL (bit 0) turns the frequency correction loop
// on, locked until the next BOOTRST; SETUSEEXRES (bit 1, MSPM0G only) selects the external ROSC resistor. The
// L11xx/L13xx FCL always uses the external resistor and has no SETUSEEXRES (dl_sysctl_mspm0l11xx_l13xx.h
// DL_SYSCTL_enableSYSOSCFCLExternalResistor writes KEY | SETUSEFCL; dl_sysctl_mspm0g1x0x_g3x0x.h writes
// KEY | SETUSEFCL | SETUSEEXRES).
inline constexpr uint32_t kFclKey = 0x2A000000;
inline constexpr uint32_t kFclSetUseFcl = 1U << 0;
inline constexpr uint32_t kFclSetUseExternalResistor = 1U << 1;
inline constexpr uint32_t kClkStatusFclMode = 1U << 24;  // CLKSTATUS.FCLMODE: SYSOSC runs in FCL mode

// RSTCAUSE.ID 4:0: the lowest-level reset cause since the last read, cleared by the read (SLAU846B Table
// 2-12 / SLAU847D Table 2-9 and the text above them; hw_sysctl_*.h RSTCAUSE).
inline constexpr uint32_t kRstcauseIdMask = 0x1F;

inline constexpr uint32_t kResetLevelSysrst = 0;
inline constexpr uint32_t kResetLevelBootloaderEntry = 2;  // hw_sysctl RESETLEVEL_LEVEL_BOOTLOADERENTRY
inline constexpr uint32_t kResetCmdGo = 0xE4000001;        // KEY 0xE4 | GO

}  // namespace bsp::mspm0::reg::sysctl
