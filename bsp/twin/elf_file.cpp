#include "elf_file.hpp"

#include <cxxabi.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

namespace twin {

namespace {

// ELF32 field offsets (System V gABI "ELF Header", "Program Header", "Section Header", "Symbol Table").
constexpr uint32_t kPtLoad = 1;
constexpr uint32_t kShtProgbits = 1, kShtSymtab = 2;
// The section holding the image's preset name (bsp/mspm0/CMakeLists.txt adds it after the link).
constexpr const char* kImageSection = ".bms_image";
constexpr uint32_t kMaxImageName = 64;
constexpr uint16_t kEtExec = 2;
constexpr uint16_t kEmArm = 40;
constexpr uint8_t kSttNotype = 0, kSttObject = 1, kSttFunc = 2;
// Flash images are bounded by the parts' flash (128 KiB on the G3507); anything far beyond is a bad file.
constexpr uint32_t kMaxFlashImage = 1U << 20;

uint16_t le16(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint16_t>(b[at] | b[at + 1] << 8);
}
uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at] | b[at + 1] << 8 | b[at + 2] << 16) | static_cast<uint32_t>(b[at + 3])
                                                                               << 24;
}

std::string demangle(const std::string& name) {
  int status = 0;
  char* text = abi::__cxa_demangle(name.c_str(), nullptr, nullptr, &status);
  if (status != 0 || text == nullptr) return name;
  std::string out = text;
  std::free(text);
  return out;
}

}  // namespace

bool ElfFile::fail(const std::string& what) {
  error_ = path_ + ": " + what;
  flash_.clear();
  symbols_.clear();
  imageName_.clear();
  return false;
}

bool ElfFile::load(const std::string& path) {
  path_ = path;
  error_.clear();
  flash_.clear();
  symbols_.clear();
  imageName_.clear();
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot read the file");
  const std::vector<uint8_t> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (b.size() < 52 || b[0] != 0x7F || b[1] != 'E' || b[2] != 'L' || b[3] != 'F')
    return fail("not an ELF file");
  if (b[4] != 1 || b[5] != 1) return fail("not a 32-bit little-endian ELF file");
  if (le16(b, 16) != kEtExec || le16(b, 18) != kEmArm) return fail("not an ARM executable");
  entry_ = le32(b, 24);
  const uint32_t phoff = le32(b, 28), shoff = le32(b, 32);
  const uint16_t phentsize = le16(b, 42), phnum = le16(b, 44), shentsize = le16(b, 46), shnum = le16(b, 48);
  const uint16_t shstrndx = le16(b, 50);
  if (phentsize < 32 || static_cast<uint64_t>(phoff) + static_cast<uint64_t>(phnum) * phentsize > b.size())
    return fail("program headers outside the file");

  for (uint16_t i = 0; i < phnum; ++i) {
    const size_t ph = phoff + static_cast<size_t>(i) * phentsize;
    const uint32_t type = le32(b, ph), offset = le32(b, ph + 4), paddr = le32(b, ph + 12);
    const uint32_t filesz = le32(b, ph + 16);
    if (type != kPtLoad || filesz == 0) continue;
    if (static_cast<uint64_t>(offset) + filesz > b.size()) return fail("a segment lies outside the file");
    if (static_cast<uint64_t>(paddr) + filesz > kMaxFlashImage)
      return fail("a loadable segment at a physical address beyond the flash of the MSPM0 parts");
    if (flash_.size() < paddr + filesz) flash_.resize(paddr + filesz, 0xFF);
    std::copy(b.begin() + offset, b.begin() + offset + filesz, flash_.begin() + paddr);
  }
  if (flash_.empty()) return fail("no loadable segment");

  if (shentsize < 40 || static_cast<uint64_t>(shoff) + static_cast<uint64_t>(shnum) * shentsize > b.size())
    return fail("section headers outside the file");
  if (shstrndx < shnum) {
    // The section names (e_shstrndx), for the one section looked up by name.
    const size_t namesSh = shoff + static_cast<size_t>(shstrndx) * shentsize;
    const uint32_t namesOffset = le32(b, namesSh + 16), namesSize = le32(b, namesSh + 20);
    if (static_cast<uint64_t>(namesOffset) + namesSize > b.size())
      return fail("a malformed section name table");
    for (uint16_t i = 0; i < shnum; ++i) {
      const size_t sh = shoff + static_cast<size_t>(i) * shentsize;
      const uint32_t nameIndex = le32(b, sh), offset = le32(b, sh + 16), size = le32(b, sh + 20);
      if (nameIndex >= namesSize || le32(b, sh + 4) != kShtProgbits) continue;
      std::string name;
      for (uint32_t k = namesOffset + nameIndex; k < namesOffset + namesSize && b[k] != 0; ++k)
        name += static_cast<char>(b[k]);
      if (name != kImageSection) continue;
      if (static_cast<uint64_t>(offset) + size > b.size() || size > kMaxImageName)
        return fail("a malformed .bms_image section");
      for (uint32_t k = offset; k < offset + size && b[k] != 0 && b[k] != '\n'; ++k)
        imageName_ += static_cast<char>(b[k]);
    }
  }
  for (uint16_t i = 0; i < shnum; ++i) {
    const size_t sh = shoff + static_cast<size_t>(i) * shentsize;
    if (le32(b, sh + 4) != kShtSymtab) continue;
    const uint32_t offset = le32(b, sh + 16), size = le32(b, sh + 20), link = le32(b, sh + 24);
    const uint32_t entsize = le32(b, sh + 36);
    if (link >= shnum || entsize < 16 || static_cast<uint64_t>(offset) + size > b.size())
      return fail("a malformed symbol table");
    const size_t strSh = shoff + static_cast<size_t>(link) * shentsize;
    const uint32_t strOffset = le32(b, strSh + 16), strSize = le32(b, strSh + 20);
    if (static_cast<uint64_t>(strOffset) + strSize > b.size()) return fail("a malformed string table");
    for (uint32_t at = offset; at + entsize <= offset + size; at += entsize) {
      const uint32_t nameIndex = le32(b, at);
      const uint8_t type = b[at + 12] & 0xF;
      // Functions, objects and linker-script symbols (__stack_top__ and the like have no type).
      if ((type != kSttFunc && type != kSttObject && type != kSttNotype) || nameIndex == 0 ||
          nameIndex >= strSize)
        continue;
      std::string name;
      for (uint32_t k = strOffset + nameIndex; k < strOffset + strSize && b[k] != 0; ++k)
        name += static_cast<char>(b[k]);
      symbols_.push_back({name, le32(b, at + 4), le32(b, at + 8), type == kSttFunc});
    }
  }
  return true;
}

std::optional<ElfSymbol> ElfFile::symbol(const std::string& name) const {
  for (const ElfSymbol& s : symbols_) {
    if (s.name == name) return s;
  }
  return std::nullopt;
}

std::string ElfFile::symbolAt(uint32_t address) const {
  for (const ElfSymbol& s : symbols_) {
    const uint32_t start = s.value & ~1U;  // Thumb function symbols have bit 0 set
    if (s.size != 0 && address >= start && address < start + s.size) return demangle(s.name);
  }
  return "";
}

bool ElfFile::patch16(uint32_t address, uint16_t value) {
  if (address + 2 > flash_.size()) return false;
  flash_[address] = static_cast<uint8_t>(value);
  flash_[address + 1] = static_cast<uint8_t>(value >> 8);
  return true;
}

bool ElfFile::patch32(uint32_t address, uint32_t value) {
  return patch16(address, static_cast<uint16_t>(value)) &&
         patch16(address + 2, static_cast<uint16_t>(value >> 16));
}

}  // namespace twin
