// Software invoke of the MSPM0 ROM bootloader (BSL): "set the RESETLEVEL as BOOTLOADERENTRY and trigger reset
// through the RESETCMD register ... all the peripheral configurations are reset" (SLAU887 3.2.2 "Application
// request"). SYSCTL RESETLEVEL (0x400B0300) = 2, then RESETCMD (0x400B0304) = KEY 0xE4 in bits 31:24 | GO
// (bit 0): hw_sysctl_mspm0{l11xx_l13xx,g1x0x_g3x0x}.h RESETLEVEL_LEVEL_BOOTLOADERENTRY, RESETCMD_KEY_VALUE,
// RESETCMD_GO_TRUE; TI's driverlib DL_SYSCTL_resetDevice(DL_SYSCTL_RESET_BOOTLOADER_ENTRY) writes the same
// two registers in this order (dl_sysctl_mspm0{l11xx_l13xx,g1x0x_g3x0x}.h). The same on the L1306 (SLAU847)
// and the G3507 (SLAU846). The BSL then listens on its UART for a Connection for 10 s (SLAU887 3.1.1).
//
// The caller is responsible for what the reset interrupts: the application must have put the pack in a safe
// state (its protection has opened the paths it controls) before it asks. Erratum BSL_ERR_01 (MSPM0G350x
// revisions B and C, SLAZ742): the software invoke fails if the application uses SRAM 0x20000EE0..0x20000FFF
// or 0x20007FF4..0x20007FFF (bsp/mspm0/README.md, Open questions).
#pragma once

namespace bsp::mspm0 {

// Writes RESETLEVEL and RESETCMD; the part resets into the BSL at once. On the host register model it
// returns.
void requestBootloaderEntry();

// Interrupts off, requestBootloaderEntry(), and wait for the reset (target only).
[[noreturn]] void enterBootloader();

}  // namespace bsp::mspm0
