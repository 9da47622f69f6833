// FlashImage: the bytes a firmware file puts into flash, and the plan for writing them through the BSL.
//
// Contract
// - load(path): an ELF (every PT_LOAD segment's file bytes at its physical = load address, as objcopy
//   writes the .hex/.bin), an Intel HEX (records 00 data, 01 end, 02 extended segment and 04 extended linear
//   address; 03/05 start addresses are ignored; every record's checksum is checked) or a raw binary placed
//   at address 0. The format is taken from the content (ELF magic, ':' first), not the name. Errors name the
//   file, and for a HEX file its line and column ("a.hex:12:10: ..."); two sources of the same byte are an
//   error.
// - Reserved flash: a range the image's ELF marks as never to be erased or written by a flasher (the data
//   flash a record store keeps): the symbols __record_store_start__ and __record_store_end__ (end
//   exclusive), or any section whose name starts with ".record_store". HEX and binary files carry no such
//   mark; they hold no bytes there either, and only the image's own sectors are ever erased.
// - checkRange(): every byte must lie in MAIN flash of the chip; the first that does not is named with its
//   region (NONMAIN, factory region, data bank, SRAM, beyond MAIN) and the image is refused. A byte in a
//   reserved range, or an image sector that shares a sector with one, is refused as well.
// - plan(): the sectors to erase (the 1 KiB sectors the image touches, merged into Flash Range Erase ranges),
//   the Program Data chunks (runs padded with 0xFF to whole 8-byte flash words, split at `maxChunk` bytes,
//   the chunk holding 0x0..0x7 (initial SP and reset vector) last, so a download cut short leaves a device
//   that boots into the BSL again: SLAU887 3.2.1), and the verification windows (the erased sectors, in
//   pieces of at most 64 KiB, SLAU887 4.3.10) with the CRC the device must report for each: the image's
//   bytes, 0xFF (erased) everywhere else.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "flash/chips.hpp"

namespace bmsctl::flash {

struct Range {
  uint32_t begin = 0, end = 0;  // [begin, end)
  uint32_t size() const { return end - begin; }
};

struct Run {
  uint32_t address = 0;
  std::vector<uint8_t> bytes;
  uint32_t end() const { return address + static_cast<uint32_t>(bytes.size()); }
};

struct ReservedRange {
  Range range;
  std::string origin;  // "symbols __record_store_start__/__record_store_end__" or "section .record_store"
};

class FlashImage {
 public:
  static std::optional<FlashImage> load(const std::string& path, std::string& error);
  // An image from runs (tests); overlapping runs are merged last-wins.
  static FlashImage fromRuns(std::vector<Run> runs, std::string path = "image");

  const std::string& path() const { return path_; }
  const char* format() const { return format_; }
  const std::vector<Run>& runs() const { return runs_; }
  const std::vector<ReservedRange>& reserved() const { return reserved_; }
  size_t byteCount() const;
  // The little-endian word at `address`, if the image holds all four bytes.
  std::optional<uint32_t> word(uint32_t address) const;
  uint8_t byteAt(uint32_t address, uint8_t fill) const;

 private:
  bool addRun(uint32_t address, std::vector<uint8_t> bytes, std::string& error, const std::string& where);
  bool loadElf(const std::vector<uint8_t>& file, std::string& error);
  bool loadHex(const std::vector<uint8_t>& file, std::string& error);

  std::string path_;
  const char* format_ = "binary";
  std::vector<Run> runs_;  // sorted, non-overlapping, touching runs merged
  std::vector<ReservedRange> reserved_;
};

// Empty if every byte may be written to `chip`'s MAIN flash; else why not (one line, naming the file).
std::string checkRange(const FlashImage& image, const Chip& chip);

struct ProgramChunk {
  uint32_t address = 0;
  std::vector<uint8_t> bytes;
};

struct VerifyWindow {
  Range range;
  uint32_t expectedCrc = 0;
};

struct FlashPlan {
  std::vector<Range> erase;  // whole sectors
  std::vector<ProgramChunk> chunks;
  std::vector<VerifyWindow> verify;
  uint32_t programBytes = 0;  // padded bytes in all chunks
};

// `maxChunk` is rounded down to a whole number of 8-byte flash words (at least one).
FlashPlan plan(const FlashImage& image, uint32_t maxChunk);
// The chunks of `chunk` split into pieces of at most `maxChunk` bytes (a smaller packet after the BSL said a
// packet was too big).
std::vector<ProgramChunk> split(const ProgramChunk& chunk, uint32_t maxChunk);

}  // namespace bmsctl::flash
