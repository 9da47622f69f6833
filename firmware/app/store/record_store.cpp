// The record store's format (README.md): why each word is written when it is.
#include "app/store/record_store.hpp"

#include <cstring>
#include <memory>

#include "core/bytes.hpp"
#include "core/crc.hpp"

namespace fw::app::store {
using namespace fw::bytes;
namespace {

constexpr uint32_t kWord = RecordStore::kWord;
constexpr uint32_t kSector = RecordStore::kSector;
constexpr uint32_t kSlotBytes = RecordStore::kSlotBytes;
constexpr uint32_t kCommit = kSlotBytes - kWord;  // offset of the commit word, the slot's last
constexpr uint8_t kCommit0 = 'C';
constexpr uint8_t kCommit1 = 'M';

// Whether `bytes` (a multiple of 4) from `p` (4-byte aligned: sectors are 1 KiB aligned, slots and words
// multiples of 8 B, the word being written alignas(4)) are all erased, in 32-bit loads: restore() checks
// every blank sector whole, and a byte at a time took 2.3 ms of the G3507 images' start-up on the twin
// (bms-sim --profile), enough to move the scans' phase against the world.
bool erased(const uint8_t* p, uint32_t bytes) {
  p = std::assume_aligned<4>(p);
  for (uint32_t off = 0; off < bytes; off += 4) {
    uint32_t w;
    std::memcpy(&w, p + off, sizeof w);
    if (w != 0xFFFFFFFFU) return false;
  }
  return true;
}

// Commit word: a mark, the CRC-16 of every other byte of the slot (header word, payload, the unused payload
// words as they read: erased), and its complement. Written last: before it exists the record does not, a
// change of any other byte of the slot fails the CRC, and a torn commit word fails the mark or the
// complement (a cut program only leaves some of its 0 bits unwritten).
void encodeCommit(uint8_t* w, uint16_t crc) {
  w[0] = kCommit0;
  w[1] = kCommit1;
  storeLe16(w + 2, crc);
  storeLe16(w + 4, static_cast<uint16_t>(~crc));
  w[6] = 0;
  w[7] = 0;
}

// Whether a written slot holds a complete record: its commit word matches and its header is in range.
bool holdsRecord(const uint8_t* slot) {
  uint8_t expect[kWord];
  encodeCommit(expect, crc::crc16Compact(slot, kCommit));
  // A loop, not memcmp: the images' runtime (bsp/mspm0/runtime.cpp) provides memset and memcpy only.
  for (uint32_t i = 0; i < kWord; ++i)
    if (slot[kCommit + i] != expect[i]) return false;
  return slot[0] < RecordStore::kTypes && slot[1] <= RecordStore::kMaxPayload && loadLe32(slot + 2) != 0;
}

}  // namespace

const uint8_t* RecordStore::at(uint32_t sector, uint32_t offset) const {
  return flash_.read().data() + sector * kSector + offset;
}

const uint8_t* RecordStore::slotAt(uint32_t slot) const {
  return at(state_->active, kWord + slot * kSlotBytes);
}

const uint8_t* RecordStore::newest(uint8_t type) const {
  const uint8_t n = state_->newest[type];
  return n == 0 ? nullptr : slotAt(n - 1U);
}

// Sector header: the generation (32 bit, 1 for the first sector ever written) and its complement. Written
// after the compaction's copies, so a valid header means the sector holds the newest record of every type.
// The complement rejects a sector whose erase was cut: an erase only sets bits, so once any bit of the
// header was erased a bit and its complement read 1 together.
bool RecordStore::headerGeneration(uint32_t sector, uint32_t& generation) const {
  const uint8_t* w = at(sector, 0);
  generation = loadLe32(w);
  return (generation ^ loadLe32(w + 4)) == 0xFFFFFFFFU && generation != 0 && generation != 0xFFFFFFFFU;
}

Status RecordStore::restore() {
  *state_ = State{};
  const uint32_t count = flash_.sectorCount();
  state_->sectors = static_cast<uint8_t>(count < kMaxSectors ? count : kMaxSectors);
  if (state_->sectors < 2) return Status::InvalidArgument;
  state_->active = state_->sectors;
  for (uint32_t s = 0; s < state_->sectors; ++s) {
    uint32_t gen = 0;
    if (headerGeneration(s, gen)) {
      state_->sector[s] = SectorState::Dirty;
      if (gen > state_->generation) {
        state_->generation = gen;
        state_->active = static_cast<uint8_t>(s);
      }
    } else {
      state_->sector[s] = erased(at(s, 0), kSector) ? SectorState::Erased : SectorState::Dirty;
    }
  }
  state_->nextSeq = 1;
  if (state_->active < state_->sectors) {
    state_->sector[state_->active] = SectorState::Active;
    scanActive();
  }
  state_->restored = true;
  return Status::Ok;
}

// The one walk of the active sector, after a restore and after a compaction: slots are written in order, so
// a later slot holds a newer record; the next record goes after the last written slot, whatever it holds
// (a record, or what a cut or failed write left of one: never read, never written again).
void RecordStore::scanActive() {
  state_->free = 0;
  std::memset(state_->newest, 0, sizeof state_->newest);
  for (uint8_t slot = 0; slot < kSlots; ++slot) {
    const uint8_t* p = slotAt(slot);
    if (erased(p, kSlotBytes)) continue;
    state_->free = static_cast<uint8_t>(slot + 1);
    if (!holdsRecord(p)) continue;
    state_->newest[p[0]] = static_cast<uint8_t>(slot + 1);
    const uint32_t seq = loadLe32(p + 2);
    if (seq >= state_->nextSeq) state_->nextSeq = seq + 1;
  }
}

Status RecordStore::read(uint8_t type, std::span<uint8_t> out, uint32_t& length) const {
  if (!state_->restored) return Status::NotReady;
  if (type >= kTypes) return Status::InvalidArgument;
  const uint8_t* p = newest(type);
  if (p == nullptr) return Status::NoResponse;
  if (out.size() < p[1]) return Status::InvalidArgument;
  std::memcpy(out.data(), p + kWord, p[1]);
  length = p[1];
  return Status::Ok;
}

uint32_t RecordStore::sequence(uint8_t type) const {
  const uint8_t* p = type < kTypes ? newest(type) : nullptr;
  return p == nullptr ? 0 : loadLe32(p + 2);
}

// Programs a record into `slot` of `sector`, word by word in order, built as it goes (no slot image on the
// stack): the header word, the payload from the second word on, every unused byte 0xFF, the commit word
// last. Words that read erased (the unused ones) are not programmed: they stay so. A compaction's copy is
// the same call with the header and payload read from the old slot, so it writes the same bytes.
Status RecordStore::writeSlot(uint32_t sector, uint32_t slot, const uint8_t* header,
                              std::span<const uint8_t> payload) {
  alignas(4) uint8_t word[kWord];
  uint16_t crc = crc::kCrc16Init;
  for (uint32_t i = 0; i < kSlotBytes; ++i) {
    const uint32_t at = i - kWord;  // in the payload (wraps below it)
    word[i % kWord] = i < kWord ? header[i] : at < payload.size() ? payload[at] : hal::FlashStorage::kErased;
    if (i % kWord != kWord - 1) continue;
    if (i < kCommit)
      crc = crc::crc16Compact(word, kWord, crc);
    else
      encodeCommit(word, crc);
    if (erased(word, kWord)) continue;
    const Status s = flash_.program(sector * kSector + kWord + slot * kSlotBytes + i / kWord * kWord,
                                    std::span<const uint8_t, kWord>(word, kWord));
    if (s != Status::Ok) return s;
  }
  return Status::Ok;
}

// Copies the newest record of each type, slot for slot (same sequence numbers), into the next erased sector
// of the ring, then writes that sector's header. A cut before the header leaves the old sector active and the
// new one Dirty (erased before its next use), so nothing is lost.
Status RecordStore::compact() {
  const uint32_t target = nextInRing(SectorState::Erased);
  if (target >= state_->sectors) return Status::Busy;
  state_->sector[target] = SectorState::Dirty;  // until its header is written
  uint32_t slot = 0;
  for (uint8_t t = 0; t < kTypes; ++t) {
    const uint8_t* p = newest(t);
    if (p == nullptr) continue;
    const Status s = writeSlot(target, slot++, p, std::span<const uint8_t>(p + kWord, p[1]));
    if (s != Status::Ok) return s;
  }
  const uint32_t gen = state_->generation + 1;
  uint8_t header[kWord];
  storeLe32(header, gen);
  storeLe32(header + 4, ~gen);
  const Status s = flash_.program(target * kSector, header);
  if (s != Status::Ok) return s;
  if (state_->active < state_->sectors) state_->sector[state_->active] = SectorState::Dirty;
  state_->sector[target] = SectorState::Active;
  state_->active = static_cast<uint8_t>(target);
  state_->generation = gen;
  scanActive();
  return Status::Ok;
}

// A record's header word: type, length, sequence number, two reserved bytes 0xFF.
Status RecordStore::write(uint8_t type, std::span<const uint8_t> payload) {
  if (!state_->restored) return Status::NotReady;
  if (type >= kTypes || payload.size() > kMaxPayload) return Status::InvalidArgument;
  if (state_->active >= state_->sectors || state_->free >= kSlots) {
    const Status s = compact();
    if (s != Status::Ok) return s;
  }
  // The slot is used whatever happens: after a failure whatever took of it is skipped, as a restore would.
  const uint8_t slot = state_->free++;
  uint8_t header[kWord] = {type, static_cast<uint8_t>(payload.size()), 0, 0, 0, 0, 0xFF, 0xFF};
  storeLe32(header + 2, state_->nextSeq);
  const Status s = writeSlot(state_->active, slot, header, payload);
  if (s != Status::Ok) return s;
  state_->newest[type] = static_cast<uint8_t>(slot + 1);
  ++state_->nextSeq;
  return Status::Ok;
}

// The first sector in `state` in ring order after the active one (from sector 0 when none is active), or
// sectors when there is none: the ring order is the order in which compaction will need them, so erasing and
// compacting in it spreads the erases evenly.
uint32_t RecordStore::nextInRing(SectorState state) const {
  const uint32_t first = state_->active < state_->sectors ? state_->active + 1U : 0;
  for (uint32_t i = 0; i < state_->sectors; ++i) {
    const uint32_t s = (first + i) % state_->sectors;
    if (state_->sector[s] == state) return s;
  }
  return state_->sectors;
}

bool RecordStore::needsErase() const {
  return nextInRing(SectorState::Dirty) < state_->sectors;
}

Status RecordStore::eraseStep() {
  if (!state_->restored) return Status::NotReady;
  const uint32_t s = nextInRing(SectorState::Dirty);
  if (s >= state_->sectors) return Status::Busy;
  const Status st = flash_.erase(s);
  if (st == Status::Ok) state_->sector[s] = SectorState::Erased;
  return st;
}

}  // namespace fw::app::store
