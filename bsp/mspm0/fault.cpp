// Target fault handling: fw::onFault, HardFault_Handler, unexpected interrupts and abort(); the start-up
// report (fault.hpp).
#include "fault.hpp"

#include "mmio.hpp"
#include "regs/sysctl.hpp"

namespace bsp::mspm0 {
namespace {

constexpr uint32_t kRecordCheck = 0xFA17C0DE;

struct NoInitRecord {
  uint32_t moduleLine;  // module << 16 | line
  uint32_t check;       // moduleLine ^ kRecordCheck: tells a written record from power-on garbage
};

// .noinit is neither loaded nor zeroed by the reset handler (see mspm0.ld).
__attribute__((section(".noinit"))) NoInitRecord gRecord;

[[noreturn]] void recordAndReset(fw::Module module, uint16_t line) {
  const uint32_t moduleLine = (static_cast<uint32_t>(module) << 16) | line;
  __asm volatile("cpsid i" ::: "memory");
  gRecord.moduleLine = moduleLine;
  gRecord.check = moduleLine ^ kRecordCheck;
  reg::sysctl::Reset& reset = reg::sysctl::reset();
  reset.resetlevel.write(reg::sysctl::kResetLevelSysrst);
  reset.resetcmd.write(reg::sysctl::kResetCmdGo);
  for (;;) {
  }
}

}  // namespace

void unexpectedInterrupt() {
  uint32_t ipsr;
  __asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  recordAndReset(fw::Module::Bsp, static_cast<uint16_t>(0xF000 | (ipsr & 0x3F)));
}

StartupReport takeStartupReport(uint8_t resetCause) {
  FaultRecord record;
  const uint32_t moduleLine = gRecord.moduleLine;
  if ((moduleLine ^ kRecordCheck) == gRecord.check) {
    record.valid = true;
    record.module = static_cast<fw::Module>(moduleLine >> 16);
    record.line = static_cast<uint16_t>(moduleLine);
  }
  gRecord.check = ~(moduleLine ^ kRecordCheck);  // taken: the next run starts without it
  return startupReport(resetCause, record);
}

}  // namespace bsp::mspm0

namespace fw {
void onFault(Module module, uint16_t line) {
  bsp::mspm0::recordAndReset(module, line);
}
}  // namespace fw

extern "C" {

void HardFault_Handler() {
  bsp::mspm0::recordAndReset(fw::Module::Bsp, 0xFFFE);
}

// libstdc++ headers may reference abort on "impossible" paths; newlib's would pull signal() and malloc.
[[noreturn]] void abort() {
  bsp::mspm0::recordAndReset(fw::Module::Core, 0xFFFD);
}

}  // extern "C"
