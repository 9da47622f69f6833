// FlashStorage: the part of the MCU's own flash reserved for data (records that survive a reset).
//
// Contract
// - The region is `sectorCount()` sectors of kSectorBytes, addressed by byte offset from its start. It holds
//   no code: the image and the ROM bootloader's area lie outside it, and nothing here can reach them.
// - An erased byte reads 0xFF. Programming writes one whole word of kWordBytes at a word-aligned offset
//   into a word that is still erased (all 0xFF): a word is programmed once between two erases of its
//   sector (the MSPM0 G-series computes ECC over the whole 64-bit word, SLAU846A FLASHCTL).
// - read() is memory-mapped and instant. erase() and program() are synchronous: on the MSPM0 a program or
//   erase stalls every read of the one flash bank, instruction fetches included, so the CPU can only wait
//   (in SRAM) until the operation ends. Each call is bounded by the data sheet's maximum time for the
//   operation (word program 275 us, sector erase 20 ms up to 2 k cycles; MSPM0L110x SLASEX5C section 7.7)
//   plus a margin; the caller schedules them when nothing urgent is pending.
// - Results, each distinct:
//     Ok               done and read back as requested;
//     InvalidArgument  sector or offset outside the region, offset not word-aligned, or the word not erased;
//     Timeout          the flash controller did not report completion within the bound;
//     VerifyFailed     the controller reported completion but the read-back differs (an erase that left a
//                      programmed byte, a word that did not take), or it reported a failure itself.
// - Power may fail at any point: a word being programmed may then read back as anything (a torn word) and a
//   sector being erased may be partly erased. The caller's record format must detect both.
// - Thread context only; not reentrant.
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"

namespace fw::hal {

class FlashStorage {
 public:
  static constexpr uint32_t kSectorBytes = 1024;  // the MSPM0 minimum erase (SLAU846A NVM terms)
  static constexpr uint32_t kWordBytes = 8;       // one flash word: 64 data bits (SLAU846A NVM terms)
  static constexpr uint8_t kErased = 0xFF;

  uint32_t sectorCount() const { return sectors_; }
  uint32_t size() const { return sectors_ * kSectorBytes; }
  std::span<const uint8_t> read() const { return {region_, size()}; }

  [[nodiscard]] Status erase(uint32_t sector) { return doErase(sector); }
  [[nodiscard]] Status program(uint32_t offset, std::span<const uint8_t, kWordBytes> word) {
    return doProgram(offset, word);
  }

 protected:
  // `region`: where the CPU reads the region (memory-mapped), `sectors` of it; both fixed for the object's
  // life (plain data, not virtual calls: the store reads through them on every access).
  constexpr FlashStorage(const uint8_t* region, uint32_t sectors) : region_(region), sectors_(sectors) {}
  ~FlashStorage() = default;

 private:
  virtual Status doErase(uint32_t sector) = 0;
  virtual Status doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) = 0;

  const uint8_t* region_;
  uint32_t sectors_;
};

}  // namespace fw::hal
