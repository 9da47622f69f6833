#include "system.hpp"

#include "bootloader_entry.hpp"
#include "fault.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"

namespace bsp::mspm0 {

namespace {
// FACTORYREGION (TI hw_factoryregion.h FACTORYREGION_OPEN_Regs): TRACEID at +0x0, DEVICEID at +0x4.
constexpr uintptr_t kFactoryRegion = 0x41C40000;
constexpr uint32_t kPartNumShift = 12, kPartNumMask = 0xFFFF;  // DEVICEID PARTNUM 27:12
}  // namespace

void Mspm0System::capture() {
  mmio::Reg& ctl = reg::cpuss::ctl(cpuss_);
  const uint32_t saved = ctl.read();
  ctl.write(reg::cpuss::kCtlPrefetch | reg::cpuss::kCtlLiteralCache);  // instruction cache off
  const mmio::Reg* factory = &mmio::block<mmio::Reg>(kFactoryRegion);
  identity_.traceId = factory[0].read();
  identity_.partNumber = static_cast<uint16_t>((factory[1].read() >> kPartNumShift) & kPartNumMask);
  ctl.write(saved);
  identity_.resetCause = takeResetCause();
}

void Mspm0System::doEnterBootloader() {
// Qualified: unqualified, the name finds SystemControl::enterBootloader(), which calls this again.
#ifdef BSP_MSPM0_MMIO_MODEL
  bsp::mspm0::requestBootloaderEntry();  // the register model records the two writes and returns
#else
  bsp::mspm0::enterBootloader();
#endif
}

}  // namespace bsp::mspm0
