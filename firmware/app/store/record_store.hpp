// RecordStore: a power-fail-safe store of small typed records in the data flash (hal::FlashStorage).
//
// Contract (format and reasoning: README.md in this folder)
// - Up to kTypes record types (0..kTypes-1), each with a payload of 0..kMaxPayload bytes. read() gives the
//   newest complete record of a type; write() appends a new one and never overwrites an older one, so a
//   power cut at any point leaves the last complete record of every type readable after restore().
// - Two or more sectors, used as a ring: one holds the records (the active sector); when it is full, write()
//   first carries the newest record of each type into the next erased sector of the ring (compaction) and
//   only then writes the new one. The old sector is then waiting to be erased: erasing is the caller's step
//   (needsErase() / eraseStep()), run when the scan's bus work allows it (a sector erase stalls the CPU for
//   up to 20 ms).
// - restore() must run first (at start-up); before it every call returns NotReady (read/write/eraseStep).
// - Results, each distinct:
//     restore:   Ok; InvalidArgument (the region has fewer than 2 sectors). It never programs or erases.
//     read:      Ok; InvalidArgument (type out of range, `out` shorter than the record); NoResponse (no
//                record of that type); NotReady.
//     write:     Ok; InvalidArgument (type out of range or payload too long); Busy (a compaction is due and
//                no erased sector is ready: run eraseStep() first; nothing was written); NotReady; or the
//                flash's Timeout / VerifyFailed / InvalidArgument / Aborted from the failing program: then
//                the new record is not stored and every earlier record is kept.
//     eraseStep: Ok (one sector erased); NotReady; Busy (nothing to erase); the flash's failure otherwise
//                (the sector stays waiting).
// - Worst-case work (S = kSlots = 12 slots a sector, N = sector count, T = kTypes):
//     restore   reads every word of every sector once and checks the CRC of at most S slots, no writes;
//     read      one copy of at most kMaxPayload bytes;
//     write     at most kSlotWords program calls, plus, when a compaction is due, at most
//               T * kSlotWords + 1 programs (each word program <= 275 us on the MSPM0) and one check of the
//               new sector's S slots;
//     eraseStep one sector erase (<= 20 ms on the MSPM0) and at most N checks.
// - Integer only, no heap, all sizes static. Thread context only; not reentrant.
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/zeroed.hpp"
#include "hal/flash.hpp"

namespace fw::app::store {

class RecordStore {
 public:
  static constexpr uint8_t kTypes = 8;
  static constexpr uint32_t kMaxPayload = 64;
  static constexpr uint32_t kMaxSectors = 16;
  static constexpr uint32_t kWord = hal::FlashStorage::kWordBytes;
  static constexpr uint32_t kSector = hal::FlashStorage::kSectorBytes;
  // Every record has a slot of the same size (README.md "Format"): its header word, the payload words
  // (room for kMaxPayload), the commit word. A sector is its header word and kSlots slots.
  static constexpr uint32_t kSlotWords = 2 + kMaxPayload / kWord;
  static constexpr uint32_t kSlotBytes = kSlotWords * kWord;
  static constexpr uint32_t kSlots = (kSector - kWord) / kSlotBytes;
  // Words programmed for a record of `length` bytes: its header, the payload, the commit word.
  static constexpr uint32_t recordWords(uint32_t length) { return 2 + (length + kWord - 1) / kWord; }

  // The state is a Zeroed block (core/zeroed.hpp): restore() sets all of it, and until then it is all zero
  // (not restored), at no constructor code on the images.
  explicit RecordStore(hal::FlashStorage& flash) : flash_(flash) {}

  [[nodiscard]] Status restore();
  [[nodiscard]] Status read(uint8_t type, std::span<uint8_t> out, uint32_t& length) const;
  [[nodiscard]] Status write(uint8_t type, std::span<const uint8_t> payload);
  bool needsErase() const;
  [[nodiscard]] Status eraseStep();

  // For tests and diagnostics: the active sector (sectorCount() when none) and the sequence number of the
  // newest record of `type` (0 when none).
  uint32_t activeSector() const { return state_->active; }
  uint32_t sequence(uint8_t type) const;

 private:
  enum class SectorState : uint8_t { Erased, Active, Dirty };

  uint32_t nextInRing(SectorState state) const;
  bool headerGeneration(uint32_t sector, uint32_t& generation) const;
  void scanActive();
  Status writeSlot(uint32_t sector, uint32_t slot, const uint8_t* header, std::span<const uint8_t> payload);
  Status compact();
  const uint8_t* at(uint32_t sector, uint32_t offset) const;
  const uint8_t* slotAt(uint32_t slot) const;
  const uint8_t* newest(uint8_t type) const;

  struct State {
    bool restored;
    uint8_t sectors;
    uint8_t active;       // == sectors when no sector holds records yet
    uint8_t free;         // the first slot of the active sector after every written one (kSlots: full)
    uint32_t generation;  // of the active sector
    uint32_t nextSeq;
    SectorState sector[kMaxSectors];
    uint8_t newest[kTypes];  // 1 + the slot of the newest record of each type in the active sector, 0 none
  };

  hal::FlashStorage& flash_;
  Zeroed<State> state_;
};

// A full compaction (every type) leaves at least one slot for the record being written.
static_assert(RecordStore::kTypes < RecordStore::kSlots);

}  // namespace fw::app::store
