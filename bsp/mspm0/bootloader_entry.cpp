#include "bootloader_entry.hpp"

#include "mmio.hpp"
#include "regs/sysctl.hpp"

namespace bsp::mspm0 {

void requestBootloaderEntry() {
  reg::sysctl::Reset& reset = reg::sysctl::reset();
  reset.resetlevel.write(reg::sysctl::kResetLevelBootloaderEntry);
  reset.resetcmd.write(reg::sysctl::kResetCmdGo);
}

#ifndef BSP_MSPM0_MMIO_MODEL
[[noreturn]] void enterBootloader() {
  __asm volatile("cpsid i" ::: "memory");
  requestBootloaderEntry();
  for (;;) {
  }
}
#endif

}  // namespace bsp::mspm0
