// Fault record, reset and start-up report for the MSPM0 target (fw::onFault, HardFault, unexpected
// interrupts; the reset cause).
//
// fw::onFault(module, line) masks interrupts, stores (module, line) with a check word in a .noinit RAM
// record, and issues a software SYSRST (SYSCTL RESETLEVEL 0 + RESETCMD KEY|GO). A SYSRST resets the CPU and
// the peripherals but keeps SRAM (SLAU846B Table 2-12 / SLAU847D Table 2-9: the SYSRST rows leave SRAM
// alone), so the next boot can read what happened. HardFault records (Bsp, 0xFFFE); an interrupt without a
// driver records (Bsp, 0xF000 | exception number); abort() records (Core, 0xFFFD).
//
// What survives which reset (the same tables): SRAM, and with it the record, survives a SYSRST (the
// software one above, a CPU lockup, a flash ECC error, BSL entry/exit, a debugger's SYSRST) and a CPURST;
// it does not survive a BOOTRST (NRST pin, software BOOTRST, and the WWDT0 watchdog: "A WWDT0 violation
// generates a BOOTRST", SLAU846B/SLAU847D WWDT overview), a BOR or a POR. After those the record is gone
// and only RSTCAUSE says what happened (0x0E for the watchdog). Keeping records across every reset needs
// flash (a later issue).
//
// Contract
// - takeResetCause(): RSTCAUSE.ID; a read clears it, so the board reads it once, first of all (system.hpp
//   Mspm0System::capture()).
// - takeStartupReport(resetCause): call once, at start-up (thread mode), with the cause the board took.
//   Returns it and the record of the previous run if one is valid and the reset kept SRAM; the record is
//   cleared either way.
#pragma once

#include <cstdint>

#include "core/assert.hpp"
#include "mmio.hpp"
#include "regs/sysctl.hpp"

namespace bsp::mspm0 {

struct FaultRecord {
  bool valid = false;
  fw::Module module = fw::Module::Bsp;
  uint16_t line = 0;
};

struct StartupReport {
  uint8_t resetCause = 0;  // SYSCTL RSTCAUSE.ID (hw_sysctl RSTCAUSE_ID_*): 0x0E WWDT0, 0x1B software SYSRST
  FaultRecord fault{};     // valid only after a reset that kept SRAM
};

// RSTCAUSE.ID values this BSP names (hw_sysctl_*.h SYSCTL_RSTCAUSE_ID_*).
inline constexpr uint8_t kResetCauseWwdt0 = 0x0E;        // "WWDT0 violation", a BOOTRST
inline constexpr uint8_t kResetCauseSysSoftware = 0x1B;  // "Software triggered SYSRST" (fw::onFault)

// Whether a reset with this cause kept SRAM: the SYSRST causes (0x10..0x1B) and the CPURST ones (0x1C,
// 0x1D) do; POR (0x01..0x03), BOR (0x04, 0x05) and BOOTRST (0x08..0x0E) reset it (SLAU846B Table 2-12,
// SLAU847D Table 2-9). 0 (nothing since the last read) keeps nothing either: no record is trusted then.
constexpr bool sramKept(uint8_t resetCause) {
  return resetCause >= 0x10 && resetCause <= 0x1D;
}

// RSTCAUSE.ID, read once: "The contents of the reset cause register are always cleared upon a read"
// (SLAU846B / SLAU847D, reset cause text above Table 2-12 / 2-9).
inline uint8_t takeResetCause() {
  return static_cast<uint8_t>(reg::sysctl::rstcause().read() & reg::sysctl::kRstcauseIdMask);
}

// The report from a reset cause and the stored record: after a reset that cleared SRAM the record's words
// are what power-up left, and a check word could match by chance, so the record counts only when SRAM was
// kept.
constexpr StartupReport startupReport(uint8_t resetCause, FaultRecord stored) {
  StartupReport report{resetCause, {}};
  if (stored.valid && sramKept(resetCause)) report.fault = stored;
  return report;
}

// Target only (fault.cpp): the .noinit record, which it clears, judged by `resetCause`.
StartupReport takeStartupReport(uint8_t resetCause);

// Body of Default_Handler (vectors_<chip>.cpp): records (Bsp, 0xF000 | exception number) and resets.
[[noreturn]] void unexpectedInterrupt();

}  // namespace bsp::mspm0
