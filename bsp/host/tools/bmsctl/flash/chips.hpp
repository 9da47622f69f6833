// The two MSPM0 parts bmsctl flashes, and what tells them apart over the ROM bootloader.
//
// - MAIN flash: 64 KiB (MSPM0L1306) / 128 KiB (MSPM0G3507) at 0x0, 1 KiB sectors (SLAU847 / SLAU846 "NVM";
//   the project's linker scripts bsp/mspm0/linker/*.ld).
// - SRAM: 4 KiB at 0x20000000 (L1306); 32 KiB at 0x20200000, also seen at 0x20000000 (G3507; the images link
//   at 0x20200000). An image's initial stack pointer (the word at 0x0) lies at the top of its part's SRAM, so
//   it names the part an image was built for, in every file format.
// - BSL buffer size, from Get Device Info: the ROM keeps two packet buffers between 0x20000160 and the 0x120
//   bytes it reserves at the top of SRAM (mspm0-sdk LP_MSPM0{L1306,G3507}/bsl/bsl_uart_flash_interface
//   README.md), so a 4 KiB part reports (0x20000EE0 - 0x20000160) / 2 = 0x06C0 (SLAU887 4.3.2's example
//   reply) and a 32 KiB part 0x3EC0 (as an LP-MSPM0G3507 answers: kalanzun/lenlab_mspm0
//   tests/firmware/test_bsl.py). Device info carries no part number; the buffer size is the only tell.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace bmsctl::flash {

struct Chip {
  const char* name;       // as --chip takes it
  const char* title;      // MSPM0L1306
  const char* launchpad;  // LP-MSPM0L1306
  uint32_t mainFlashSize;
  uint32_t sramBase, sramSize;  // where its images put the stack
  uint32_t sramAliasBase;       // another window onto the same SRAM (0 = none)
  uint16_t bslBufferSize;
  // How to start the ROM bootloader by hand on this LaunchPad, and where its UART is.
  const char* invokeProcedure;
};

inline constexpr uint32_t kSectorSize = 1024;

std::span<const Chip> chips();
const Chip* chipByName(const std::string& name);
// The part whose SRAM holds `initialStackPointer` (its top included), nullptr if none.
const Chip* chipFromStack(uint32_t initialStackPointer);
// The part whose ROM BSL reports this buffer size, nullptr if none.
const Chip* chipFromBslBuffer(uint16_t bufferSize);

}  // namespace bmsctl::flash
