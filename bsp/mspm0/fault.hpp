// Fault record and reset for the MSPM0 target (fw::onFault, HardFault, unexpected interrupts).
//
// fw::onFault(module, line) masks interrupts, stores (module, line) with a check word in a .noinit RAM
// record, and issues a software SYSRST (SYSCTL RESETLEVEL 0 + RESETCMD KEY|GO). A SYSRST resets the CPU and
// the peripherals but keeps SRAM (SLAU846A 2.4 reset table; a BOOTRST would power-cycle SRAM and lose the
// record), so the next boot can read what happened. HardFault records (Bsp, 0xFFFE); an interrupt without
// a driver records (Bsp, 0xF000 | exception number); abort() records (Core, 0xFFFD). The WWDT reset also
// keeps SRAM, so a record plus RSTCAUSE tell a watchdog reset from a fault.
//
// Contract
// - takeFaultRecord() returns the record of the previous run, if one is valid, and clears it. Call it once
//   after start-up (task or thread mode).
#pragma once

#include <cstdint>

#include "core/assert.hpp"

namespace bsp::mspm0 {

struct FaultRecord {
  bool valid = false;
  fw::Module module = fw::Module::Bsp;
  uint16_t line = 0;
};

FaultRecord takeFaultRecord();

// Body of Default_Handler (vectors_<chip>.cpp): records (Bsp, 0xF000 | exception number) and resets.
[[noreturn]] void unexpectedInterrupt();

}  // namespace bsp::mspm0
