#include "flash/flash_image.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>

#include "flash/bsl_packet.hpp"

namespace bmsctl::flash {

namespace {

constexpr uint32_t kWord = 8;               // MSPM0 flash word: 64 bits (SLAU887 4.3.4, 8-byte alignment)
constexpr uint32_t kMaxVerify = 64 * 1024;  // Standalone Verification: 1 KiB .. 64 KiB (SLAU887 4.3.10)
const char* const kReservedStart = "__record_store_start__";
const char* const kReservedEnd = "__record_store_end__";

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

uint32_t rd32(const std::vector<uint8_t>& f, size_t at) {
  return static_cast<uint32_t>(f[at]) | static_cast<uint32_t>(f[at + 1]) << 8 |
         static_cast<uint32_t>(f[at + 2]) << 16 | static_cast<uint32_t>(f[at + 3]) << 24;
}
uint16_t rd16(const std::vector<uint8_t>& f, size_t at) {
  return static_cast<uint16_t>(f[at] | f[at + 1] << 8);
}

uint32_t floorTo(uint32_t v, uint32_t unit) {
  return v / unit * unit;
}
uint32_t ceilTo(uint32_t v, uint32_t unit) {
  return (v + unit - 1) / unit * unit;
}

bool overlaps(const Range& a, const Range& b) {
  return a.begin < b.end && b.begin < a.end;
}

// Where an address lies when it is not MAIN flash (MSPM0 memory map: SLAU846/SLAU847 "Memory map"; NONMAIN
// 0x41C00000..0x41C003FF, the factory region at 0x41C40000, the data bank at 0x41D00000 as TI's OpenOCD
// driver src/flash/nor/mspm0.c lays them out).
std::string regionName(uint32_t address, const Chip& chip) {
  if (address >= 0x41C00000 && address < 0x41C00400) {
    return "NONMAIN flash (0x41C00000..0x41C003FF, the boot and BSL configuration)";
  }
  if (address >= 0x41C40000 && address < 0x41D00000) return "the factory region (0x41C40000..)";
  if (address >= 0x41D00000 && address < 0x41E00000) return "the data bank (0x41D00000..)";
  if (address >= 0x20000000 && address < 0x20400000) {
    return "SRAM (0x20000000..; a load segment without a flash load address?)";
  }
  if (address < 0x00400000) return std::string("flash beyond the ") + chip.title + "'s MAIN flash";
  return "no flash at all";
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Loading

bool FlashImage::addRun(uint32_t address, std::vector<uint8_t> bytes, std::string& error,
                        const std::string& where) {
  if (bytes.empty()) return true;
  if (static_cast<uint64_t>(address) + bytes.size() > 0x100000000ULL) {
    error = where + ": bytes at " + hex32(address) + " run past the end of the address space";
    return false;
  }
  Run run{address, std::move(bytes)};
  auto it = std::lower_bound(runs_.begin(), runs_.end(), run.address,
                             [](const Run& r, uint32_t a) { return r.address < a; });
  if ((it != runs_.end() && it->address < run.end()) ||
      (it != runs_.begin() && std::prev(it)->end() > address)) {
    error = where + ": bytes at " + hex32(address) + " are given twice";
    return false;
  }
  it = runs_.insert(it, std::move(run));
  // Merge with touching neighbours.
  if (std::next(it) != runs_.end() && it->end() == std::next(it)->address) {
    it->bytes.insert(it->bytes.end(), std::next(it)->bytes.begin(), std::next(it)->bytes.end());
    runs_.erase(std::next(it));
  }
  if (it != runs_.begin() && std::prev(it)->end() == it->address) {
    auto prev = std::prev(it);
    prev->bytes.insert(prev->bytes.end(), it->bytes.begin(), it->bytes.end());
    runs_.erase(it);
  }
  return true;
}

std::optional<FlashImage> FlashImage::load(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open the image file";
    return std::nullopt;
  }
  std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  FlashImage image;
  image.path_ = path;
  if (file.empty()) {
    error = path + ": the file is empty";
    return std::nullopt;
  }
  bool ok;
  if (file.size() >= 4 && file[0] == 0x7F && file[1] == 'E' && file[2] == 'L' && file[3] == 'F') {
    image.format_ = "ELF";
    ok = image.loadElf(file, error);
  } else if (file[0] == ':') {
    image.format_ = "Intel HEX";
    ok = image.loadHex(file, error);
  } else {
    image.format_ = "binary";
    ok = image.addRun(0, std::move(file), error, path);
  }
  if (!ok) return std::nullopt;
  if (image.runs_.empty()) {
    error = path + ": the image holds no bytes to program";
    return std::nullopt;
  }
  return image;
}

FlashImage FlashImage::fromRuns(std::vector<Run> runs, std::string path) {
  std::map<uint32_t, uint8_t> bytes;
  for (const Run& r : runs) {
    for (size_t i = 0; i < r.bytes.size(); ++i)
      bytes[r.address + static_cast<uint32_t>(i)] = r.bytes[i];
  }
  FlashImage image;
  image.path_ = std::move(path);
  for (const auto& [address, value] : bytes) {
    if (!image.runs_.empty() && image.runs_.back().end() == address) {
      image.runs_.back().bytes.push_back(value);
    } else {
      image.runs_.push_back({address, {value}});
    }
  }
  return image;
}

// ELF32 little-endian ARM (System V gABI; ARM IHI 0044): the load segments and, for reserved flash, the
// symbol table and the section names.
bool FlashImage::loadElf(const std::vector<uint8_t>& f, std::string& error) {
  auto fail = [&](const std::string& what) {
    error = path_ + ": " + what;
    return false;
  };
  if (f.size() < 52 || f[4] != 1 || f[5] != 1) return fail("not a 32-bit little-endian ELF file");
  if (rd16(f, 18) != 40) return fail("not an ARM ELF file (e_machine " + std::to_string(rd16(f, 18)) + ")");
  const uint32_t phoff = rd32(f, 28), shoff = rd32(f, 32);
  const uint16_t phentsize = rd16(f, 42), phnum = rd16(f, 44), shentsize = rd16(f, 46), shnum = rd16(f, 48);
  const uint16_t shstrndx = rd16(f, 50);
  if (phnum == 0) return fail("no program headers: not a linked image");
  if (phentsize < 32 || phoff + static_cast<uint64_t>(phentsize) * phnum > f.size())
    return fail("program headers outside the file");
  for (uint16_t i = 0; i < phnum; ++i) {
    const size_t ph = phoff + static_cast<size_t>(i) * phentsize;
    if (rd32(f, ph) != 1 /* PT_LOAD */) continue;
    const uint32_t offset = rd32(f, ph + 4), paddr = rd32(f, ph + 12), filesz = rd32(f, ph + 16);
    if (filesz == 0) continue;  // .bss-like: nothing to program
    if (static_cast<uint64_t>(offset) + filesz > f.size())
      return fail("load segment " + std::to_string(i) + " lies outside the file");
    std::vector<uint8_t> bytes(f.begin() + offset, f.begin() + offset + filesz);
    if (!addRun(paddr, std::move(bytes), error, path_ + ": load segment " + std::to_string(i))) return false;
  }
  // Sections: names, and the symbol table.
  if (shnum == 0 || shentsize < 40 || shoff + static_cast<uint64_t>(shentsize) * shnum > f.size())
    return true;
  auto section = [&](uint16_t i) { return shoff + static_cast<size_t>(i) * shentsize; };
  auto stringAt = [&](uint32_t table, uint32_t at) {
    std::string s;
    for (size_t p = table + at; p < f.size() && f[p] != 0; ++p)
      s += static_cast<char>(f[p]);
    return s;
  };
  const uint32_t shstr = shstrndx < shnum ? rd32(f, section(shstrndx) + 16) : 0;
  std::optional<uint32_t> symStart, symEnd;
  for (uint16_t i = 0; i < shnum; ++i) {
    const size_t sh = section(i);
    const std::string name = shstr ? stringAt(shstr, rd32(f, sh)) : "";
    const uint32_t type = rd32(f, sh + 4), addr = rd32(f, sh + 12), offset = rd32(f, sh + 16);
    const uint32_t size = rd32(f, sh + 20), link = rd32(f, sh + 24);
    if (name.rfind(".record_store", 0) == 0 && size > 0) {
      reserved_.push_back({{addr, addr + size}, "section " + name});
    }
    if (type != 2 /* SHT_SYMTAB */ || link >= shnum || static_cast<uint64_t>(offset) + size > f.size())
      continue;
    const uint32_t strtab = rd32(f, section(static_cast<uint16_t>(link)) + 16);
    for (uint32_t s = offset; s + 16 <= offset + size; s += 16) {
      const std::string sym = stringAt(strtab, rd32(f, s));
      if (sym == kReservedStart) symStart = rd32(f, s + 4);
      if (sym == kReservedEnd) symEnd = rd32(f, s + 4);
    }
  }
  if (symStart && symEnd && *symEnd > *symStart) {
    reserved_.push_back(
        {{*symStart, *symEnd}, std::string("symbols ") + kReservedStart + "/" + kReservedEnd});
  }
  return true;
}

// Intel HEX (Intel "Hexadecimal Object File Format Specification" rev. A): ":LLAAAATT<data>CC" per line.
bool FlashImage::loadHex(const std::vector<uint8_t>& f, std::string& error) {
  uint32_t base = 0;
  bool ended = false;
  size_t lineNo = 0;
  size_t pos = 0;
  while (pos < f.size()) {
    size_t eol = pos;
    while (eol < f.size() && f[eol] != '\n')
      ++eol;
    std::string line(f.begin() + pos, f.begin() + eol);
    pos = eol + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    auto fail = [&](size_t column, const std::string& what) {
      error = path_ + ":" + std::to_string(lineNo) + ":" + std::to_string(column) + ": " + what;
      return false;
    };
    if (line.empty()) continue;
    if (ended) return fail(1, "a record after the end-of-file record");
    if (line[0] != ':') return fail(1, "a record must start with ':'");
    if (line.size() < 11 || (line.size() - 1) % 2 != 0) return fail(1, "record too short or of odd length");
    std::vector<uint8_t> rec;
    for (size_t i = 1; i < line.size(); i += 2) {
      auto digit = [](char c) {
        return c >= '0' && c <= '9'   ? c - '0'
               : c >= 'A' && c <= 'F' ? c - 'A' + 10
               : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                      : -1;
      };
      const int hi = digit(line[i]), lo = digit(line[i + 1]);
      if (hi < 0 || lo < 0) return fail(hi < 0 ? i + 1 : i + 2, "not a hex digit");
      rec.push_back(static_cast<uint8_t>(hi << 4 | lo));
    }
    const size_t count = rec[0];
    if (rec.size() != count + 5) {
      return fail(2, "the byte count says " + std::to_string(count) + " data bytes, the record has " +
                         std::to_string(rec.size() > 5 ? rec.size() - 5 : 0));
    }
    uint8_t sum = 0;
    for (uint8_t b : rec)
      sum = static_cast<uint8_t>(sum + b);
    if (sum != 0) return fail(line.size() - 1, "checksum mismatch");
    const uint32_t offset = static_cast<uint32_t>(rec[1] << 8 | rec[2]);
    const uint8_t type = rec[3];
    const std::vector<uint8_t> data(rec.begin() + 4, rec.end() - 1);
    switch (type) {
      case 0x00:
        if (!addRun(base + offset, data, error, path_ + ":" + std::to_string(lineNo) + ":4")) return false;
        break;
      case 0x01:
        ended = true;
        break;
      case 0x02:
      case 0x04:
        if (count != 2) return fail(2, "an address record has 2 data bytes");
        base = type == 0x04 ? static_cast<uint32_t>(data[0] << 8 | data[1]) << 16
                            : static_cast<uint32_t>(data[0] << 8 | data[1]) << 4;
        break;
      case 0x03:
      case 0x05:
        break;  // start address: the part starts from its reset vector
      default:
        return fail(8, "unknown record type " + std::to_string(type));
    }
  }
  if (!ended) {
    error = path_ + ":" + std::to_string(lineNo) + ":1: no end-of-file record: the file is cut short";
    return false;
  }
  return true;
}

size_t FlashImage::byteCount() const {
  size_t n = 0;
  for (const Run& r : runs_)
    n += r.bytes.size();
  return n;
}

uint8_t FlashImage::byteAt(uint32_t address, uint8_t fill) const {
  auto it = std::upper_bound(runs_.begin(), runs_.end(), address,
                             [](uint32_t a, const Run& r) { return a < r.address; });
  if (it == runs_.begin()) return fill;
  --it;
  return address < it->end() ? it->bytes[address - it->address] : fill;
}

std::optional<uint32_t> FlashImage::word(uint32_t address) const {
  uint32_t value = 0;
  for (uint32_t i = 0; i < 4; ++i) {
    const uint8_t a = byteAt(address + i, 0x00), b = byteAt(address + i, 0xFF);
    if (a != b) return std::nullopt;  // not in the image
    value |= static_cast<uint32_t>(a) << (8 * i);
  }
  return value;
}

// ---------------------------------------------------------------------------------------------------------
// Checks and plan

std::string checkRange(const FlashImage& image, const Chip& chip) {
  const Range main{0, chip.mainFlashSize};
  for (const Run& r : image.runs()) {
    if (r.end() <= main.end) continue;
    const uint32_t first = std::max(r.address, main.end);
    return image.path() + ": " + std::to_string(r.end() - first) + " bytes at " + hex32(first) + ".." +
           hex32(r.end() - 1) + " lie in " + regionName(first, chip) + ", outside MAIN flash of the " +
           chip.title + " (" + hex32(0) + ".." + hex32(main.end - 1) + "); bmsctl writes MAIN flash only";
  }
  for (const ReservedRange& res : image.reserved()) {
    for (const Run& r : image.runs()) {
      const Range bytes{r.address, r.end()};
      const Range sectors{floorTo(r.address, kSectorSize), ceilTo(r.end(), kSectorSize)};
      if (overlaps(bytes, res.range)) {
        return image.path() + ": the image has bytes in the reserved flash " + hex32(res.range.begin) + ".." +
               hex32(res.range.end - 1) + " (" + res.origin + "), which a flasher never writes";
      }
      if (overlaps(sectors, res.range)) {
        return image.path() + ": the image's sectors " + hex32(sectors.begin) + ".." +
               hex32(sectors.end - 1) + " share a sector with the reserved flash " + hex32(res.range.begin) +
               ".." + hex32(res.range.end - 1) + " (" + res.origin + "): erasing them would destroy it";
      }
    }
  }
  return "";
}

std::vector<ProgramChunk> split(const ProgramChunk& chunk, uint32_t maxChunk) {
  maxChunk = std::max(kWord, floorTo(maxChunk, kWord));
  std::vector<ProgramChunk> out;
  for (size_t at = 0; at < chunk.bytes.size(); at += maxChunk) {
    const size_t n = std::min<size_t>(maxChunk, chunk.bytes.size() - at);
    out.push_back({chunk.address + static_cast<uint32_t>(at),
                   std::vector<uint8_t>(chunk.bytes.begin() + static_cast<long>(at),
                                        chunk.bytes.begin() + static_cast<long>(at + n))});
  }
  return out;
}

FlashPlan plan(const FlashImage& image, uint32_t maxChunk) {
  // Whole flash words: each run padded out to 8-byte boundaries, runs that share a word merged (a word is
  // programmed once).
  std::vector<Range> words;
  for (const Run& r : image.runs()) {
    const Range w{floorTo(r.address, kWord), ceilTo(r.end(), kWord)};
    if (!words.empty() && w.begin <= words.back().end) {
      words.back().end = std::max(words.back().end, w.end);
    } else {
      words.push_back(w);
    }
  }
  FlashPlan p;
  std::optional<ProgramChunk> resetVector;
  for (const Range& w : words) {
    ProgramChunk c{w.begin, {}};
    for (uint32_t a = w.begin; a < w.end; ++a)
      c.bytes.push_back(image.byteAt(a, 0xFF));
    p.programBytes += w.size();
    if (c.address == 0) {  // the initial SP and reset vector go last
      resetVector = ProgramChunk{0, std::vector<uint8_t>(c.bytes.begin(), c.bytes.begin() + kWord)};
      c.bytes.erase(c.bytes.begin(), c.bytes.begin() + kWord);
      c.address = kWord;
    }
    for (ProgramChunk& piece : split(c, maxChunk))
      p.chunks.push_back(std::move(piece));
  }
  if (resetVector) p.chunks.push_back(std::move(*resetVector));

  for (const Range& w : words) {
    const Range s{floorTo(w.begin, kSectorSize), ceilTo(w.end, kSectorSize)};
    if (!p.erase.empty() && s.begin <= p.erase.back().end) {
      p.erase.back().end = std::max(p.erase.back().end, s.end);
    } else {
      p.erase.push_back(s);
    }
  }
  for (const Range& e : p.erase) {
    for (uint32_t at = e.begin; at < e.end; at += kMaxVerify) {
      VerifyWindow v{{at, std::min(e.end, at + kMaxVerify)}, 0};
      std::vector<uint8_t> expected;
      expected.reserve(v.range.size());
      for (uint32_t a = v.range.begin; a < v.range.end; ++a)
        expected.push_back(image.byteAt(a, 0xFF));
      v.expectedCrc = bsl::crc32(expected);
      p.verify.push_back(v);
    }
  }
  return p;
}

}  // namespace bmsctl::flash
