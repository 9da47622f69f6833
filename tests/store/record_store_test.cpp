// RecordStore on the host flash model: round trips, newest-wins, compaction and wear, flash failures,
// corrupted and random flash contents.
#include "app/store/record_store.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "sim/sim_flash.hpp"
#include "store/store_script.hpp"

using bsp::host::SimFlash;
using fw::Status;
using fw::app::store::RecordStore;
using store_test::Bytes;
using store_test::scriptItem;

namespace {

Bytes readBack(const RecordStore& store, uint8_t type, Status& status) {
  uint8_t buf[RecordStore::kMaxPayload];
  uint32_t length = 0;
  status = store.read(type, buf, length);
  return status == Status::Ok ? Bytes(buf, buf + length) : Bytes{};
}

// Writes items first..first+count-1, erasing whenever the store asks; returns the newest payload per type.
void writeItems(RecordStore& store, uint32_t first, uint32_t count, std::map<uint8_t, Bytes>& newest) {
  for (uint32_t i = first; i < first + count; ++i) {
    if (store.needsErase()) {
      ASSERT_EQ(store.eraseStep(), Status::Ok);
    }
    const auto item = scriptItem(i);
    ASSERT_EQ(store.write(item.type, item.payload), Status::Ok) << "write " << i;
    newest[item.type] = item.payload;
  }
}

void expectNewest(const RecordStore& store, const std::map<uint8_t, Bytes>& newest) {
  for (uint8_t t = 0; t < RecordStore::kTypes; ++t) {
    Status s{};
    const Bytes got = readBack(store, t, s);
    const auto it = newest.find(t);
    if (it == newest.end()) {
      EXPECT_EQ(s, Status::NoResponse) << "type " << int(t);
    } else {
      EXPECT_EQ(s, Status::Ok) << "type " << int(t);
      EXPECT_EQ(got, it->second) << "type " << int(t);
    }
  }
}

}  // namespace

TEST(RecordStore, CallsBeforeRestoreAreNotReady) {
  SimFlash flash(2);
  RecordStore store(flash);
  const uint8_t p[1] = {1};
  EXPECT_EQ(store.write(0, p), Status::NotReady);
  EXPECT_EQ(store.eraseStep(), Status::NotReady);
  Status s{};
  readBack(store, 0, s);
  EXPECT_EQ(s, Status::NotReady);
}

TEST(RecordStore, OneSectorIsRefused) {
  SimFlash flash(1);
  RecordStore store(flash);
  EXPECT_EQ(store.restore(), Status::InvalidArgument);
}

TEST(RecordStore, EmptyFlashHasNoRecords) {
  SimFlash flash(2);
  RecordStore store(flash);
  ASSERT_EQ(store.restore(), Status::Ok);
  expectNewest(store, {});
  EXPECT_FALSE(store.needsErase());
  EXPECT_EQ(store.eraseStep(), Status::Busy);
}

TEST(RecordStore, ArgumentsAreChecked) {
  SimFlash flash(2);
  RecordStore store(flash);
  ASSERT_EQ(store.restore(), Status::Ok);
  uint8_t big[RecordStore::kMaxPayload + 1] = {};
  EXPECT_EQ(store.write(0, big), Status::InvalidArgument);
  EXPECT_EQ(store.write(RecordStore::kTypes, std::span<const uint8_t>(big, 4)), Status::InvalidArgument);
  ASSERT_EQ(store.write(1, std::span<const uint8_t>(big, 16)), Status::Ok);
  uint8_t small[8];
  uint32_t length = 0;
  EXPECT_EQ(store.read(1, small, length), Status::InvalidArgument);
  EXPECT_EQ(store.read(RecordStore::kTypes, big, length), Status::InvalidArgument);
  EXPECT_EQ(store.write(2, std::span<const uint8_t>()), Status::Ok);  // an empty record is a record
  EXPECT_EQ(store.read(2, small, length), Status::Ok);
  EXPECT_EQ(length, 0U);
}

TEST(RecordStore, EachRecordTypeRoundTripsAcrossRestore) {
  SimFlash flash(2);
  std::map<uint8_t, Bytes> newest;
  {
    RecordStore store(flash);
    ASSERT_EQ(store.restore(), Status::Ok);
    writeItems(store, 0, 4, newest);  // the skewed cycle writes each of the four types once
    ASSERT_EQ(newest.size(), 4U);
    expectNewest(store, newest);
  }
  RecordStore again(flash);
  ASSERT_EQ(again.restore(), Status::Ok);
  expectNewest(again, newest);
}

TEST(RecordStore, NewestWinsAndSequenceGrows) {
  SimFlash flash(3);
  RecordStore store(flash);
  ASSERT_EQ(store.restore(), Status::Ok);
  std::map<uint8_t, Bytes> newest;
  writeItems(store, 0, 40, newest);
  const uint32_t seq = store.sequence(0);
  RecordStore again(flash);
  ASSERT_EQ(again.restore(), Status::Ok);
  expectNewest(again, newest);
  EXPECT_EQ(again.sequence(0), seq);
  writeItems(again, 40, 1, newest);
  EXPECT_GT(std::max({again.sequence(0), again.sequence(1), again.sequence(2), again.sequence(3)}), seq);
}

TEST(RecordStore, CompactionKeepsEveryTypeAndWearIsEven) {
  for (uint32_t sectors : {2U, 3U, 4U, 7U}) {
    SimFlash flash(sectors);
    RecordStore store(flash);
    ASSERT_EQ(store.restore(), Status::Ok);
    std::map<uint8_t, Bytes> newest;
    // Type 5 is written once, first, and must survive every compaction after it.
    const uint8_t once[3] = {0xAB, 0xCD, 0xEF};
    ASSERT_EQ(store.write(5, once), Status::Ok);
    newest[5] = Bytes(once, once + 3);
    writeItems(store, 0, 3000, newest);
    expectNewest(store, newest);
    uint32_t lo = 0xFFFFFFFF, hi = 0;
    for (uint32_t s = 0; s < sectors; ++s) {
      lo = std::min(lo, flash.eraseCount(s));
      hi = std::max(hi, flash.eraseCount(s));
    }
    EXPECT_GT(lo, 10U) << sectors << " sectors";
    EXPECT_LE(hi - lo, 1U) << sectors << " sectors";
    RecordStore again(flash);
    ASSERT_EQ(again.restore(), Status::Ok);
    expectNewest(again, newest);
    std::printf("REPORT store.wear sectors=%u writes=3001 erases per sector min=%u max=%u\n", sectors, lo,
                hi);
  }
}

TEST(RecordStore, CompactionWithoutAnErasedSectorIsBusyUntilErased) {
  SimFlash flash(2);
  RecordStore store(flash);
  ASSERT_EQ(store.restore(), Status::Ok);
  std::map<uint8_t, Bytes> newest;
  Status s = Status::Ok;
  uint32_t i = 0;
  // Never erasing: the first compaction uses the erased second sector, the next one finds none.
  for (; i < 1000 && s == Status::Ok; ++i) {
    const auto item = scriptItem(i);
    s = store.write(item.type, item.payload);
    if (s == Status::Ok) newest[item.type] = item.payload;
  }
  ASSERT_EQ(s, Status::Busy);
  EXPECT_TRUE(store.needsErase());
  expectNewest(store, newest);
  ASSERT_EQ(store.eraseStep(), Status::Ok);
  EXPECT_FALSE(store.needsErase());
  writeItems(store, i - 1, 1, newest);
  expectNewest(store, newest);
}

TEST(RecordStore, FlashFailuresReturnTheirStatusAndLoseNothing) {
  for (Status failure : {Status::Timeout, Status::VerifyFailed}) {
    SimFlash flash(3);
    RecordStore store(flash);
    ASSERT_EQ(store.restore(), Status::Ok);
    std::map<uint8_t, Bytes> newest;
    uint32_t failures = 0;
    for (uint32_t i = 0; i < 400; ++i) {
      if (store.needsErase()) {
        if (i % 11 == 0) {  // a failed erase leaves the sector waiting
          flash.failNext(failure);
          ASSERT_EQ(store.eraseStep(), failure);
          ASSERT_TRUE(store.needsErase());
        }
        ASSERT_EQ(store.eraseStep(), Status::Ok);
      }
      const auto item = scriptItem(i);
      if (i % 7 == 3) {  // one program of this write fails: a compaction's copy, the header, payload, commit
        flash.failNext(failure,
                       (i / 7) % RecordStore::recordWords(static_cast<uint32_t>(item.payload.size())));
        ASSERT_EQ(store.write(item.type, item.payload), failure) << i;
        ++failures;
        expectNewest(store, newest);
        continue;
      }
      ASSERT_EQ(store.write(item.type, item.payload), Status::Ok) << i;
      newest[item.type] = item.payload;
      // A reset now restores everything, the writes after the failed one's unused words included.
      RecordStore reset(flash);
      ASSERT_EQ(reset.restore(), Status::Ok);
      expectNewest(reset, newest);
      if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(failures, 50U);
    RecordStore again(flash);
    ASSERT_EQ(again.restore(), Status::Ok);
    expectNewest(again, newest);
  }
}

TEST(RecordStore, ACorruptedRecordIsNeverReturned) {
  // Flip each byte of the newest record of a type in turn: the store must fall back to the record before
  // it (or none), never return the altered one.
  SimFlash reference(2);
  std::map<uint8_t, Bytes> before;
  {
    RecordStore store(reference);
    ASSERT_EQ(store.restore(), Status::Ok);
    writeItems(store, 0, 10, before);  // no compaction before the next write (2 sectors)
  }
  const auto last = scriptItem(10);
  std::map<uint8_t, Bytes> after = before;
  after[last.type] = last.payload;
  // The record spans the words its write changed, from its header to its commit word.
  uint32_t first = 0, end = 0;
  {
    RecordStore store(reference);
    ASSERT_EQ(store.restore(), Status::Ok);
    const Bytes old(reference.image().begin(), reference.image().end());
    ASSERT_EQ(store.write(last.type, last.payload), Status::Ok);
    auto img = reference.image();
    for (uint32_t off = 0; off < img.size(); ++off)
      if (img[off] != old[off]) {
        if (end == 0) first = off / 8 * 8;
        end = (off / 8 + 1) * 8;
      }
    ASSERT_GE(end - first, RecordStore::recordWords(static_cast<uint32_t>(last.payload.size())) * 8);
  }
  uint32_t tried = 0;
  for (uint32_t byte = first; byte < end; ++byte) {
    for (uint8_t mask : {0x01, 0x80, 0xFF}) {
      SimFlash flash(2);
      std::copy(reference.image().begin(), reference.image().end(), flash.image().begin());
      flash.image()[byte] ^= mask;
      RecordStore store(flash);
      ASSERT_EQ(store.restore(), Status::Ok);
      Status s{};
      const Bytes got = readBack(store, last.type, s);
      const auto prev = before.find(last.type);
      // A flipped header or commit bit loses the record; a payload change fails the CRC.
      if (prev == before.end()) {
        EXPECT_EQ(s, Status::NoResponse) << byte;
      } else {
        EXPECT_EQ(s, Status::Ok);
        EXPECT_EQ(got, prev->second) << "byte " << byte << " mask " << int(mask);
      }
      // Still writable.
      std::map<uint8_t, Bytes> more;
      writeItems(store, 100, 3, more);
      ++tried;
    }
  }
  EXPECT_EQ(tried, (end - first) * 3);
}

TEST(RecordStore, RandomFlashContentsNeverCrashAndCanBeErasedIntoAWorkingStore) {
  uint64_t x = 0x9E3779B97F4A7C15ULL;
  for (uint32_t round = 0; round < 300; ++round) {
    SimFlash flash(3, round + 1);
    auto img = flash.image();
    for (auto& b : img) {
      x ^= x << 13;
      x ^= x >> 7;
      x ^= x << 17;
      // Mostly erased with written islands, so some headers and records look plausible.
      b = (x % 4 == 0) ? static_cast<uint8_t>(x >> 8) : 0xFF;
    }
    if (round % 3 == 0) {  // a valid sector header in front of random words
      const uint8_t hdr[8] = {5, 0, 0, 0, static_cast<uint8_t>(~5), 0xFF, 0xFF, 0xFF};  // generation 5
      std::copy(hdr, hdr + 8, img.begin());
    }
    RecordStore store(flash);
    ASSERT_EQ(store.restore(), Status::Ok);
    for (uint8_t t = 0; t < RecordStore::kTypes; ++t) {
      Status s{};
      readBack(store, t, s);
      EXPECT_TRUE(s == Status::Ok || s == Status::NoResponse);
    }
    std::map<uint8_t, Bytes> newest;
    writeItems(store, round, 60, newest);
    RecordStore again(flash);
    ASSERT_EQ(again.restore(), Status::Ok);
    expectNewest(again, newest);
  }
}
