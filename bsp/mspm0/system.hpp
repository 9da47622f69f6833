// Mspm0System: fw::hal::SystemControl on an MSPM0: the chip's identity and the software-invoke reset into
// the ROM bootloader.
//
// - capture() (once, in the board's bringUp(), before anything else reads RSTCAUSE): reads FACTORYREGION
//   TRACEID (0x41C40000) and DEVICEID (0x41C40004, PARTNUM bits 27:12: 0xBB82 on the MSPM0L11xx/L13xx, 0xBB88
//   on the G1x0x/G3x0x, as TI's IAR low-power patch scripts test it) (TI hw_factoryregion.h,
//   FACTORYREGION_OPEN_Regs: "TRACEID ... defined by TI, during ATE, based on wafer"; the same addresses on
//   both parts, FACTORYREGION_BASE in mspm0l130x.h and mspm0g350x.h) with the instruction cache off, as
//   TI's DL_FactoryRegion_getTraceID reads it (regs/cpuss.hpp CTL), and SYSCTL RSTCAUSE (fault.hpp
//   takeResetCause(): this is its one reader, a read clears it; the Startup message takes the cause from
//   identity()). identity() returns what capture() read.
// - enterBootloader(): the software-invoke reset into the ROM bootloader (bootloader_entry.hpp: interrupts
//   masked, RESETLEVEL = BOOTLOADERENTRY, RESETCMD = KEY | GO). Never returns on the target.
#pragma once

#include "hal/system.hpp"

namespace bsp::mspm0 {

class Mspm0System final : public fw::hal::SystemControl {
 public:
  constexpr explicit Mspm0System(uintptr_t cpussBase) : cpuss_(cpussBase) {}
  void capture();

 private:
  fw::hal::ChipIdentity doIdentity() const override { return identity_; }
  void doEnterBootloader() override;

  uintptr_t cpuss_;
  fw::hal::ChipIdentity identity_{};
};

}  // namespace bsp::mspm0
