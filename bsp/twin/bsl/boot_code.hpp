// BootCode: what the MSPM0 boot code decides after a reset: run the image from its reset vector, or start the
// ROM bootloader (rom_bsl.hpp) and hold the core. Registered as the chip's last reset hook, so every model is
// reset before it looks.
//
// The BSL is started (SLAU887 3.2 "BSL invocation"; the factory configuration enables it with pin invoke,
// fast boot off: mspm0-sdk boot_config.c):
// - after a software reset with RESETLEVEL = BOOTLOADERENTRY (2): "set the RESETLEVEL as BOOTLOADERENTRY and
//   trigger reset through the RESETCMD register" (SLAU887 3.2.2; Sysctl::takeBootRequest());
// - by the boot code, which a BOOTRST or POR runs (a plain SYSRST resets the CPU and peripherals only,
//   SLAU846B/SLAU847D reset levels): when the invoke pin PA18 is high (SLAU887 3.2.3; the data sheets'
//   BSL_invoke "must be HIGH during BOOTRST"; on the LaunchPads S1 pulls it high against a pull-down), or
//   when MAIN flash is blank: the initial stack pointer (0x0) and the reset vector (0x4) both erased (SLAU887
//   3.2.1);
// - after the BSL's own exit reset (RESETLEVEL 4: "Bootloader exit, rerun of Bootcode, which in turn starts
//   the application", SLAU887 4.3.11) only if MAIN flash is blank; the invoke pin is not looked at.
#pragma once

#include <string>

#include "bsl/rom_bsl.hpp"
#include "machine.hpp"
#include "periph/pins.hpp"
#include "periph/sysctl.hpp"

namespace twin {

class BootCode {
 public:
  BootCode(Machine& machine, Sysctl& sysctl, Pins& pins, RomBsl& bsl, int invokePincm);
  // Why the last reset started the BSL, or "" if it started the image.
  const std::string& bslReason() const { return reason_; }

 private:
  void afterReset(ResetKind kind);
  bool flashBlank() const;

  Machine& machine_;
  Sysctl& sysctl_;
  Pins& pins_;
  RomBsl& bsl_;
  int invokePincm_;
  std::string reason_;
};

}  // namespace twin
