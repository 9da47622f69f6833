// Power cut at every flash operation of a write sequence: every word program (with each way the word can be
// left torn) and every sector erase. After each cut a fresh store restores the last complete record of each
// type (or the one being written, if its commit word took), never a torn one, and stays writable.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "app/store/record_store.hpp"
#include "sim/sim_flash.hpp"
#include "store/store_script.hpp"

using bsp::host::SimFlash;
using fw::Status;
using fw::app::store::RecordStore;
using store_test::Bytes;
using store_test::scriptItem;

namespace {

constexpr uint32_t kWrites = 80;  // enough for several compactions and erases on 2 and 3 sectors

struct Progress {
  std::map<uint8_t, Bytes> complete;  // the newest write of each type that returned Ok
  bool inFlight = false;              // a write was cut
  uint8_t inFlightType = 0;
  Bytes inFlightPayload;
};

// Runs the write sequence (erasing whenever the store asks) until it ends or the power is cut.
Progress runUntilCut(SimFlash& flash) {
  Progress p;
  RecordStore store(flash);
  EXPECT_EQ(store.restore(), Status::Ok);
  for (uint32_t i = 0; i < kWrites; ++i) {
    if (store.needsErase()) {
      const Status s = store.eraseStep();
      if (s == Status::Aborted) return p;
      EXPECT_EQ(s, Status::Ok);
    }
    const auto item = scriptItem(i);
    const Status s = store.write(item.type, item.payload);
    if (s == Status::Aborted) {
      p.inFlight = true;
      p.inFlightType = item.type;
      p.inFlightPayload = item.payload;
      return p;
    }
    EXPECT_EQ(s, Status::Ok) << "write " << i;
    p.complete[item.type] = item.payload;
  }
  return p;
}

// After the cut: restore, check each type, then keep writing and check again after another restore.
void checkAfterCut(SimFlash& flash, const Progress& p, const char* what, uint32_t cut) {
  flash.powerOn();
  RecordStore store(flash);
  ASSERT_EQ(store.restore(), Status::Ok);
  std::map<uint8_t, Bytes> newest;
  for (uint8_t t = 0; t < RecordStore::kTypes; ++t) {
    uint8_t buf[RecordStore::kMaxPayload];
    uint32_t length = 0;
    const Status s = store.read(t, buf, length);
    const Bytes got = s == Status::Ok ? Bytes(buf, buf + length) : Bytes{};
    const auto done = p.complete.find(t);
    const bool cutThisType = p.inFlight && p.inFlightType == t;
    if (cutThisType && s == Status::Ok && got == p.inFlightPayload) {
      newest[t] = got;
      continue;
    }
    if (done == p.complete.end()) {
      ASSERT_EQ(s, Status::NoResponse) << what << " cut " << cut << " type " << int(t);
    } else {
      ASSERT_EQ(s, Status::Ok) << what << " cut " << cut << " type " << int(t);
      ASSERT_EQ(got, done->second) << what << " cut " << cut << " type " << int(t);
      newest[t] = got;
    }
  }
  for (uint32_t i = 200; i < 240; ++i) {
    if (store.needsErase()) {
      ASSERT_EQ(store.eraseStep(), Status::Ok) << what << " cut " << cut;
    }
    const auto item = scriptItem(i);
    ASSERT_EQ(store.write(item.type, item.payload), Status::Ok) << what << " cut " << cut << " then " << i;
    newest[item.type] = item.payload;
  }
  RecordStore again(flash);
  ASSERT_EQ(again.restore(), Status::Ok);
  for (const auto& [t, payload] : newest) {
    uint8_t buf[RecordStore::kMaxPayload];
    uint32_t length = 0;
    ASSERT_EQ(again.read(t, buf, length), Status::Ok);
    ASSERT_EQ(Bytes(buf, buf + length), payload) << what << " cut " << cut;
  }
}

}  // namespace

TEST(RecordStorePowerCut, EveryProgramAndEveryEraseOfAWriteSequence) {
  uint32_t cuts = 0;
  for (uint32_t sectors : {2U, 3U}) {
    SimFlash clean(sectors);
    runUntilCut(clean);
    const uint32_t programs = clean.programCount();
    const uint32_t erases = clean.eraseCount();
    ASSERT_GT(erases, 2U) << "the sequence must compact and erase";
    for (uint32_t n = 0; n < programs; ++n) {
      for (auto tear : {SimFlash::Tear::Erased, SimFlash::Tear::Partial, SimFlash::Tear::Random,
                        SimFlash::Tear::Complete}) {
        SimFlash flash(sectors, n * 4 + static_cast<uint32_t>(tear) + 1);
        flash.cutAtProgram(n, tear);
        const Progress p = runUntilCut(flash);
        ASSERT_TRUE(flash.powerLost());
        checkAfterCut(flash, p, "program", n);
        if (::testing::Test::HasFatalFailure()) return;
        ++cuts;
      }
    }
    for (uint32_t e = 0; e < erases; ++e) {
      for (uint32_t seed = 1; seed <= 4; ++seed) {
        SimFlash flash(sectors, e * 8 + seed);
        flash.cutAtErase(e);
        const Progress p = runUntilCut(flash);
        ASSERT_TRUE(flash.powerLost());
        checkAfterCut(flash, p, "erase", e);
        if (::testing::Test::HasFatalFailure()) return;
        ++cuts;
      }
    }
  }
  std::printf(
      "REPORT store.power_cuts=%u (every word program x 4 tear kinds and every erase x 4 partial "
      "patterns of an 80-write sequence, 2 and 3 sectors; host SimFlash)\n",
      cuts);
}
