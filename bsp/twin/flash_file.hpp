// FlashFile: the image's flash data region (bsp/mspm0/linker: __record_store_start__ .. __record_store_end__)
// kept in a file across twin runs (bms-sim --elf ... --flash FILE), so a run after a reset scenario starts
// with what the last one left in flash, as a board that lost power would.
//
// Contract
// - dataRegion(): the region's bounds from the ELF's symbols; nullopt if the image has none.
// - load(): the file holds exactly the region's bytes; a missing file is created erased (0xFF). Any other
//   size, or a file that cannot be read or created, is an error and the flash is left as the image put it.
// - save(): writes the region's bytes as the machine's flash holds them now.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "elf_file.hpp"
#include "machine.hpp"

namespace twin {

struct FlashRegion {
  uint32_t begin = 0, end = 0;
};

// The region as the linker scripts place it on both parts (bsp/mspm0/linker/mspm0_sections.ld DATA), for a
// twin started without an ELF (twin-bsl on a blank part).
inline constexpr FlashRegion kLinkerDataRegion{0x7000, 0x8000};

std::optional<FlashRegion> dataRegion(const ElfFile& elf);
bool loadFlashFile(Machine& machine, FlashRegion region, const std::string& path, std::string& error);
bool saveFlashFile(const Machine& machine, FlashRegion region, const std::string& path, std::string& error);

}  // namespace twin
