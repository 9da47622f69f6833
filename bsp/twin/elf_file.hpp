// ElfFile: the little of ELF32 (System V gABI, ARM ELF IHI 0044) the twin needs from a firmware image: the
// bytes a programmer writes to flash, and the symbol table.
//
// Contract
// - load(path) reads the whole file and checks it: ELF32, little endian, EM_ARM, executable. Any problem is a
//   false return with error() saying what (the file name first), and nothing half-loaded is kept.
// - flashImage(): every PT_LOAD segment's file bytes placed at its physical (load) address, as objcopy -O
//   binary / the .hex would put them; gaps are 0xFF (erased flash). .data's initial values are therefore at
//   their flash (load) address, where the reset handler copies them from.
// - symbol(name) / symbolAt(address): the .symtab entries (functions and objects); symbolAt returns the
//   function or object containing the address ("" if none), demangled.
// - imageName(): the image's preset name, the text of its `.bms_image` section (a section the MSPM0 build
//   adds to every image, not loaded: bsp/mspm0/CMakeLists.txt), "" when the file has none.
// - patch16(address, value): changes a halfword of the flash image (tests build broken variants of an image).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace twin {

struct ElfSymbol {
  std::string name;  // as in the file (mangled)
  uint32_t value = 0;
  uint32_t size = 0;
  bool function = false;
};

class ElfFile {
 public:
  bool load(const std::string& path);
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }

  const std::vector<uint8_t>& flashImage() const { return flash_; }
  uint32_t entry() const { return entry_; }
  std::optional<ElfSymbol> symbol(const std::string& name) const;
  std::string symbolAt(uint32_t address) const;
  const std::vector<ElfSymbol>& symbols() const { return symbols_; }
  const std::string& imageName() const { return imageName_; }
  bool patch16(uint32_t address, uint16_t value);
  bool patch32(uint32_t address, uint32_t value);

 private:
  bool fail(const std::string& what);

  std::string path_;
  std::string error_;
  std::vector<uint8_t> flash_;
  std::vector<ElfSymbol> symbols_;
  std::string imageName_;
  uint32_t entry_ = 0;
};

}  // namespace twin
