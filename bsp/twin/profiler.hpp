// Profiler: where an image spends its CPU cycles on the twin, by function (from the ELF's symbols) and by
// exception, so performance and low-power work is measured on the image itself (bms-sim --elf --profile).
//
// Counting (every cycle the core is busy lands in exactly one function row and one exception row):
// - an instruction's cycles (cpu/timing.hpp, an exception return's frame pop included) go to the function
//   whose symbol covers its address ("[no symbol]" if none) and to the exception whose code it is (IPSR at
//   the instruction; 0 = Thread);
// - an exception entry's 15 cycles go to the row "[exception entry]" and to the exception entered;
// - a call is an arrival at a function's first instruction from another function (BL, BLX, a tail branch).
// Sleep (WFI) is the run's cycles minus the busy ones.
//
// The report format (stable: tools may parse it; bsp/twin/README.md "Profile" documents it): text, one
// record per line, tab-separated fields, '#' lines are comments:
//   profile  1                                   format version
//   image    <preset>
//   elf      <path>
//   clock_hz <Hz>
//   run_cycles <n>  busy_cycles <n>  sleep_cycles <n>   (one per line, key TAB value)
//   exception <number> <name> <entries> <cycles> <pct_of_busy>        number 0 = Thread; name = the vector's
//                                                                     handler symbol; most cycles first
//   function  <name> <calls> <cycles> <pct_of_busy> <address> <size>  most cycles first, ties by name
// pct_of_busy has two decimals; address is 0x%08X; names are demangled and contain no tab.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "cpu/nvic.hpp"
#include "elf_file.hpp"

namespace twin {

class Profiler {
 public:
  explicit Profiler(const ElfFile& elf);

  // One step of the core: an instruction at `pc` (IPSR `ipsr`), or an exception entry (`entry`) into
  // `entered`, taking `cycles`.
  void account(uint32_t pc, uint32_t ipsr, uint32_t entered, bool entry, uint32_t cycles) {
    if (entry) {
      rows_[kEntryRow].cycles += cycles;
      exceptions_[entered].cycles += cycles;
      ++exceptions_[entered].entries;
      last_ = kEntryRow;
      return;
    }
    exceptions_[ipsr & 0x3F].cycles += cycles;
    size_t row = last_;
    if (row >= kFirstFunction && pc - rows_[row].start < rows_[row].size) {
      rows_[row].cycles += cycles;
      return;
    }
    row = find(pc);
    if (pc == rows_[row].start && row != last_) ++rows_[row].calls;
    rows_[row].cycles += cycles;
    last_ = row;
  }

  // The report (format above). `runCycles`: the run's length; `busyCycles`: the machine's busy cycles.
  void write(std::ostream& out, const std::string& image, uint64_t clockHz, uint64_t runCycles,
             uint64_t busyCycles) const;

 private:
  static constexpr size_t kEntryRow = 0, kUnknownRow = 1, kFirstFunction = 2;
  struct Row {
    std::string name;
    uint32_t start = 0, size = 0;
    uint64_t calls = 0, cycles = 0;
  };
  struct ExceptionRow {
    uint64_t entries = 0, cycles = 0;
  };
  size_t find(uint32_t pc) const;

  const ElfFile& elf_;
  std::vector<Row> rows_;  // sorted by start from kFirstFunction on
  std::vector<ExceptionRow> exceptions_ = std::vector<ExceptionRow>(64);
  size_t last_ = kUnknownRow;
};

}  // namespace twin
