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
constexpr uint8_t kSectorMagic0 = 'S';
constexpr uint8_t kSectorMagic1 = 'T';
constexpr uint8_t kHeaderMark = 0x5A;
constexpr uint8_t kCommit0 = 'C';
constexpr uint8_t kCommit1 = 'M';
constexpr uint32_t kGenerationMask = 0xFFFFFF;

// Whether `bytes` (a multiple of 4) from `p` (word aligned: sectors are 1 KiB aligned, words 8 B) are all
// erased, in 32-bit loads: restore() checks every blank sector whole, and a byte at a time through at()
// took 2.3 ms of the G3507 images' start-up on the twin (bms-sim --profile), enough to move the scans'
// phase against the world.
bool erased(const uint8_t* p, uint32_t bytes) {
  p = std::assume_aligned<4>(p);
  for (uint32_t off = 0; off < bytes; off += 4) {
    uint32_t w;
    std::memcpy(&w, p + off, sizeof w);
    if (w != 0xFFFFFFFFU) return false;
  }
  return true;
}

void store24(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
  p[2] = static_cast<uint8_t>(v >> 16);
}
uint32_t load24(const uint8_t* p) {
  return p[0] | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16);
}

// Record header word: type, length, sequence (LE), a mark, CRC-8 of the first seven bytes. Its own CRC lets a
// scan trust the length to find the next record even when the record's commit word never got written.
struct Header {
  uint8_t type;
  uint8_t length;
  uint32_t seq;
};
void encodeHeader(uint8_t* w, const Header& h) {
  w[0] = h.type;
  w[1] = h.length;
  storeLe32(w + 2, h.seq);
  w[6] = kHeaderMark;
  w[7] = crc::crc8(w, 7);
}
bool decodeHeader(const uint8_t* w, Header& h) {
  if (w[6] != kHeaderMark || crc::crc8(w, 7) != w[7]) return false;
  h = Header{w[0], w[1], loadLe32(w + 2)};
  return h.type < RecordStore::kTypes && h.length <= RecordStore::kMaxPayload && h.seq != 0;
}

// Commit word: a mark, the CRC-16 over the header word and the payload words (padding included, so any
// changed bit of the record fails it), and its complement. Written last: before it
// exists the record does not, and a torn commit word fails the mark, the CRC or the complement.
uint32_t paddedLength(uint32_t length) {
  return (length + kWord - 1) / kWord * kWord;
}
uint16_t recordCrc(const uint8_t* header, const uint8_t* payloadWords, uint32_t length) {
  return crc::crc16Compact(payloadWords, paddedLength(length), crc::crc16Compact(header, kWord));
}
void encodeCommit(uint8_t* w, uint16_t crc) {
  w[0] = kCommit0;
  w[1] = kCommit1;
  storeLe16(w + 2, crc);
  storeLe16(w + 4, static_cast<uint16_t>(~crc));
  w[6] = 0;
  w[7] = 0;
}
bool commitMatches(const uint8_t* w, uint16_t crc) {
  uint8_t expect[kWord];
  encodeCommit(expect, crc);
  // A loop, not memcmp: the images' runtime (bsp/mspm0/runtime.cpp) provides memset and memcpy only.
  for (uint32_t i = 0; i < kWord; ++i)
    if (w[i] != expect[i]) return false;
  return true;
}

}  // namespace

const uint8_t* RecordStore::at(uint32_t sector, uint32_t offset) const {
  return flash_.read().data() + sector * kSector + offset;
}

// Sector header: magic, generation (24 bits) and its complement. Written after the compaction's copies, so a
// valid header means the sector holds the newest record of every type. The complement also rejects a sector
// whose erase was cut (an erase only sets bits, so a bit and its complement cannot both survive as 1/0 pairs
// once either was erased).
bool RecordStore::headerGeneration(uint32_t sector, uint32_t& generation) const {
  const uint8_t* w = at(sector, 0);
  if (w[0] != kSectorMagic0 || w[1] != kSectorMagic1) return false;
  generation = load24(w + 2);
  return ((generation ^ load24(w + 5)) == kGenerationMask) && generation != 0;
}

Status RecordStore::restore() {
  state_->restored = false;
  state_->sectors = flash_.sectorCount() < kMaxSectors ? flash_.sectorCount() : kMaxSectors;
  if (state_->sectors < 2) return Status::InvalidArgument;
  state_->active = state_->sectors;
  state_->generation = 0;
  for (uint32_t s = 0; s < state_->sectors; ++s) {
    uint32_t gen = 0;
    if (headerGeneration(s, gen)) {
      state_->sector[s] = SectorState::Dirty;
      if (gen > state_->generation) {
        state_->generation = gen;
        state_->active = s;
      }
    } else {
      state_->sector[s] = erased(at(s, 0), kSector) ? SectorState::Erased : SectorState::Dirty;
    }
  }
  for (Entry& e : state_->index)
    e = Entry{};
  state_->nextSeq = 1;
  state_->free = kSector;
  if (state_->active < state_->sectors) {
    state_->sector[state_->active] = SectorState::Active;
    scanActive();
  }
  state_->restored = true;
  return Status::Ok;
}

// Walks the active sector's records (at most W - 1 of them). A header that fails its check ends the walk and
// closes the sector to appends (its length cannot be trusted); so does a written word after the first erased
// header slot. A record without a valid commit word is skipped by its length.
void RecordStore::scanActive() {
  uint32_t off = kWord;
  state_->free = kSector;
  while (off + kWord <= kSector) {
    const uint8_t* w = at(state_->active, off);
    if (erased(w, kWord)) {
      if (erased(w, kSector - off)) state_->free = off;
      return;
    }
    Header h{};
    if (!decodeHeader(w, h)) return;
    const uint32_t words = recordWords(h.length);
    if (off + words * kWord > kSector) return;
    if (h.seq >= state_->nextSeq) state_->nextSeq = h.seq + 1;
    const uint8_t* commit = at(state_->active, off + (words - 1) * kWord);
    if (commitMatches(commit, recordCrc(w, w + kWord, h.length)) && h.seq > state_->index[h.type].seq)
      state_->index[h.type] = Entry{static_cast<uint16_t>(off), h.length, h.seq};
    off += words * kWord;
  }
}

Status RecordStore::read(uint8_t type, std::span<uint8_t> out, uint32_t& length) const {
  if (!state_->restored) return Status::NotReady;
  if (type >= kTypes) return Status::InvalidArgument;
  const Entry& e = state_->index[type];
  if (e.seq == 0) return Status::NoResponse;
  if (out.size() < e.length) return Status::InvalidArgument;
  std::memcpy(out.data(), at(state_->active, e.offset + kWord), e.length);
  length = e.length;
  return Status::Ok;
}

Status RecordStore::programWord(uint32_t sector, uint32_t offset, const uint8_t* word) {
  return flash_.program(sector * kSector + offset, std::span<const uint8_t, kWord>(word, kWord));
}

// Copies the newest record of each type, word for word (same sequence numbers), into the next sector of the
// ring, then writes that sector's header. A cut before the header leaves the old sector active and the new
// one Dirty (erased before its next use), so nothing is lost.
Status RecordStore::compact(uint32_t& target) {
  target = state_->active < state_->sectors ? (state_->active + 1) % state_->sectors : 0;
  if (state_->active >= state_->sectors) {
    for (uint32_t i = 0; i < state_->sectors && state_->sector[target] != SectorState::Erased; ++i)
      target = (target + 1) % state_->sectors;
  }
  if (state_->sector[target] != SectorState::Erased) return Status::Busy;
  state_->sector[target] = SectorState::Dirty;  // until its header is written
  uint32_t off = kWord;
  Entry moved[kTypes]{};
  for (uint8_t t = 0; t < kTypes; ++t) {
    const Entry& e = state_->index[t];
    if (e.seq == 0) continue;
    const uint32_t words = recordWords(e.length);
    for (uint32_t i = 0; i < words; ++i) {
      const Status s = programWord(target, off + i * kWord, at(state_->active, e.offset + i * kWord));
      if (s != Status::Ok) return s;
    }
    moved[t] = Entry{static_cast<uint16_t>(off), e.length, e.seq};
    off += words * kWord;
  }
  const uint32_t gen = (state_->generation + 1) & kGenerationMask;
  uint8_t header[kWord] = {kSectorMagic0, kSectorMagic1};
  store24(header + 2, gen);
  store24(header + 5, ~gen & kGenerationMask);
  const Status s = programWord(target, 0, header);
  if (s != Status::Ok) return s;
  if (state_->active < state_->sectors) state_->sector[state_->active] = SectorState::Dirty;
  state_->sector[target] = SectorState::Active;
  state_->active = target;
  state_->generation = gen;
  state_->free = off;
  for (uint8_t t = 0; t < kTypes; ++t)
    state_->index[t] = moved[t];
  return Status::Ok;
}

Status RecordStore::append(uint8_t type, std::span<const uint8_t> payload) {
  const uint32_t length = static_cast<uint32_t>(payload.size());
  const uint32_t words = recordWords(length);
  const uint32_t start = state_->free;
  uint8_t header[kWord];
  encodeHeader(header, Header{type, static_cast<uint8_t>(length), state_->nextSeq});
  Status s = programWord(state_->active, start, header);
  uint16_t crc = crc::crc16Compact(header, kWord);
  for (uint32_t i = 0; s == Status::Ok && i + 2 < words; ++i) {
    uint8_t word[kWord] = {};  // padding 0x00
    const uint32_t n = length - i * kWord < kWord ? length - i * kWord : kWord;
    std::memcpy(word, payload.data() + i * kWord, n);
    crc = crc::crc16Compact(word, kWord, crc);
    s = programWord(state_->active, start + (i + 1) * kWord, word);
  }
  if (s == Status::Ok) {
    uint8_t commit[kWord];
    encodeCommit(commit, crc);
    s = programWord(state_->active, start + (words - 1) * kWord, commit);
  }
  if (s != Status::Ok) {
    // Where the next record goes is whatever a restore would find now: a header slot the failed program
    // left erased is used again, a header that took makes the scan skip the record by its length, a header
    // left unreadable closes the sector (the next write compacts). Otherwise an erased gap would end a later
    // restore's scan and hide the records written after it.
    scanActive();
    return s;
  }
  state_->free = start + words * kWord;
  state_->index[type] = Entry{static_cast<uint16_t>(start), static_cast<uint8_t>(length), state_->nextSeq};
  ++state_->nextSeq;
  return Status::Ok;
}

Status RecordStore::write(uint8_t type, std::span<const uint8_t> payload) {
  if (!state_->restored) return Status::NotReady;
  if (type >= kTypes || payload.size() > kMaxPayload) return Status::InvalidArgument;
  const uint32_t need = recordWords(static_cast<uint32_t>(payload.size())) * kWord;
  if (state_->active >= state_->sectors || state_->free + need > kSector) {
    uint32_t target = 0;
    const Status s = compact(target);
    if (s != Status::Ok) return s;
  }
  return append(type, payload);
}

bool RecordStore::needsErase() const {
  for (uint32_t s = 0; s < state_->sectors; ++s)
    if (state_->sector[s] == SectorState::Dirty) return true;
  return false;
}

// Erases the first Dirty sector after the active one in ring order: the ring order is the order in which
// compaction will need them, and it spreads the erases evenly.
Status RecordStore::eraseStep() {
  if (!state_->restored) return Status::NotReady;
  const uint32_t first = state_->active < state_->sectors ? state_->active + 1 : 0;
  for (uint32_t i = 0; i < state_->sectors; ++i) {
    const uint32_t s = (first + i) % state_->sectors;
    if (state_->sector[s] != SectorState::Dirty) continue;
    const Status st = flash_.erase(s);
    if (st == Status::Ok) state_->sector[s] = SectorState::Erased;
    return st;
  }
  return Status::Busy;
}

}  // namespace fw::app::store
