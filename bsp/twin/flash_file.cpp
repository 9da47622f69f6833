#include "flash_file.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <vector>

namespace twin {

std::optional<FlashRegion> dataRegion(const ElfFile& elf) {
  const auto begin = elf.symbol("__record_store_start__");
  const auto end = elf.symbol("__record_store_end__");
  if (!begin || !end || end->value <= begin->value) return std::nullopt;
  return FlashRegion{begin->value, end->value};
}

bool loadFlashFile(Machine& machine, FlashRegion region, const std::string& path, std::string& error) {
  auto& flash = machine.flash();
  if (region.end > flash.size()) {
    error = "the data region ends beyond the part's flash";
    return false;
  }
  const size_t bytes = region.end - region.begin;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fill(flash.begin() + region.begin, flash.begin() + region.end, 0xFF);
    return saveFlashFile(machine, region, path, error);  // created erased
  }
  const std::vector<uint8_t> content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (content.size() != bytes) {
    error = path + ": " + std::to_string(content.size()) + " B, the data region is " + std::to_string(bytes) +
            " B";
    return false;
  }
  std::copy(content.begin(), content.end(), flash.begin() + region.begin);
  return true;
}

bool saveFlashFile(const Machine& machine, FlashRegion region, const std::string& path, std::string& error) {
  const auto& flash = machine.flash();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(flash.data() + region.begin),
            static_cast<std::streamsize>(region.end - region.begin));
  if (!out) {
    error = path + ": cannot write";
    return false;
  }
  return true;
}

}  // namespace twin
