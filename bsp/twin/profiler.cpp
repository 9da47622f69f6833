#include "profiler.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace twin {

Profiler::Profiler(const ElfFile& elf) : elf_(elf) {
  rows_.push_back({"[exception entry]", 0, 0, 0, 0});
  rows_.push_back({"[no symbol]", 0, 0, 0, 0});
  std::vector<Row> functions;
  for (const ElfSymbol& s : elf.symbols()) {
    if (!s.function || s.size == 0) continue;
    const uint32_t start = s.value & ~1U;
    // Aliases (two names for one address) keep the first name.
    if (std::any_of(functions.begin(), functions.end(), [&](const Row& r) { return r.start == start; }))
      continue;
    functions.push_back({elf.symbolAt(start), start, s.size, 0, 0});
  }
  std::sort(functions.begin(), functions.end(), [](const Row& a, const Row& b) { return a.start < b.start; });
  rows_.insert(rows_.end(), functions.begin(), functions.end());
}

size_t Profiler::find(uint32_t pc) const {
  // The last function starting at or below pc, if it covers pc.
  auto it = std::upper_bound(rows_.begin() + kFirstFunction, rows_.end(), pc,
                             [](uint32_t a, const Row& r) { return a < r.start; });
  if (it == rows_.begin() + kFirstFunction) return kUnknownRow;
  --it;
  if (pc - it->start >= it->size) return kUnknownRow;
  return static_cast<size_t>(it - rows_.begin());
}

void Profiler::write(std::ostream& out, const std::string& image, uint64_t clockHz, uint64_t runCycles,
                     uint64_t busyCycles) const {
  auto pct = [&](uint64_t cycles) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f",
                  busyCycles ? 100.0 * static_cast<double>(cycles) / static_cast<double>(busyCycles) : 0.0);
    return std::string(buf);
  };
  auto clean = [](std::string s) {
    std::replace(s.begin(), s.end(), '\t', ' ');
    return s;
  };
  out << "# bms-sim --profile: cycles per exception and per function (bsp/twin/README.md \"Profile\")\n";
  out << "profile\t1\n";
  out << "image\t" << clean(image) << "\n";
  out << "elf\t" << clean(elf_.path()) << "\n";
  out << "clock_hz\t" << clockHz << "\n";
  out << "run_cycles\t" << runCycles << "\n";
  out << "busy_cycles\t" << busyCycles << "\n";
  out << "sleep_cycles\t" << (runCycles > busyCycles ? runCycles - busyCycles : 0) << "\n";

  // The vector table at 0 (the images' VTOR): exception n's handler is the word at 4n.
  const std::vector<uint8_t>& flash = elf_.flashImage();
  auto handlerName = [&](int n) -> std::string {
    if (n == 0) return "Thread";
    const size_t at = 4 * static_cast<size_t>(n);
    if (at + 4 > flash.size()) return "exception " + std::to_string(n);
    const uint32_t vector = static_cast<uint32_t>(flash[at] | flash[at + 1] << 8 | flash[at + 2] << 16) |
                            static_cast<uint32_t>(flash[at + 3]) << 24;
    const std::string name = elf_.symbolAt(vector & ~1U);
    return name.empty() ? "exception " + std::to_string(n) : name;
  };
  std::vector<int> order;
  for (int n = 0; n < static_cast<int>(exceptions_.size()); ++n) {
    if (exceptions_[static_cast<size_t>(n)].cycles != 0) order.push_back(n);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return exceptions_[static_cast<size_t>(a)].cycles > exceptions_[static_cast<size_t>(b)].cycles;
  });
  out << "# exception\tnumber\tname\tentries\tcycles\tpct_of_busy\n";
  for (int n : order) {
    const ExceptionRow& e = exceptions_[static_cast<size_t>(n)];
    out << "exception\t" << n << "\t" << clean(handlerName(n)) << "\t" << e.entries << "\t" << e.cycles
        << "\t" << pct(e.cycles) << "\n";
  }
  std::vector<const Row*> rows;
  for (const Row& r : rows_) {
    if (r.cycles != 0) rows.push_back(&r);
  }
  std::sort(rows.begin(), rows.end(), [](const Row* a, const Row* b) {
    return a->cycles != b->cycles ? a->cycles > b->cycles : a->name < b->name;
  });
  out << "# function\tname\tcalls\tcycles\tpct_of_busy\taddress\tsize\n";
  for (const Row* r : rows) {
    char address[16];
    std::snprintf(address, sizeof address, "0x%08X", r->start);
    out << "function\t" << clean(r->name) << "\t" << r->calls << "\t" << r->cycles << "\t" << pct(r->cycles)
        << "\t" << address << "\t" << r->size << "\n";
  }
}

}  // namespace twin
