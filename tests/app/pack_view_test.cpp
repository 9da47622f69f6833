// summarize(): the totals it computes equal the ones its contract defines (pack_view.hpp), computed here the
// plain way (every board's cells walked for the open-wire verdict, then every reading folded in order), over
// random packs of 1..64 boards: boards that failed or never validated, open wires by a low cell, a kNoReading
// cell or a step between neighbours (at and around the limits), temperatures with no reading, and readings
// drawn from a few values so that extremes tie (the earlier place wins).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "app/pack/pack_view.hpp"

namespace {

using fw::app::BoardSample;
using fw::app::kCellFloorMv;
using fw::app::kMaxCellsPerBoard;
using fw::app::kMaxTempsPerBoard;
using fw::app::kNoReading;
using fw::app::kOpenWireStepMv;
using fw::app::PackTotals;
using fw::app::PackView;

struct Reference {
  PackTotals t{};
  uint16_t commErrors = 0;
};

// The contract, walked one reading at a time.
Reference plainSummary(const PackView& view, fw::Instant scanEnd, uint16_t commErrorsBefore) {
  Reference ref;
  PackTotals& t = ref.t;
  ref.commErrors = commErrorsBefore;
  t.takenAt = scanEnd;
  t.oldest = scanEnd;
  uint16_t whole = 0;
  auto take = [](int16_t v, uint16_t place, bool& seen, int16_t* ext, uint16_t* at) {
    if (!seen || v > ext[0]) ext[0] = v, at[0] = place;
    if (!seen || v < ext[1]) ext[1] = v, at[1] = place;
    seen = true;
  };
  for (uint16_t b = 0; b < view.boards.size(); ++b) {
    const BoardSample& s = view.boards[b];
    if (!s.valid) {
      t.oldest = fw::Instant{};
    } else if (fw::isBefore(s.takenAt, t.oldest) && t.oldest.us != 0) {
      t.oldest = s.takenAt;
    }
    if (s.last != fw::Status::Ok) {
      if (ref.commErrors != UINT16_MAX) ++ref.commErrors;
      continue;
    }
    if (!s.valid) continue;
    bool open = false;
    for (uint8_t c = 0; c < view.cellsPerBoard; ++c) {
      const int32_t v = s.cellMv[c];
      if (v < kCellFloorMv) open = true;
      if (c + 1 < view.cellsPerBoard) {
        const int32_t step = s.cellMv[c + 1] - v;
        if (step > kOpenWireStepMv || step < -kOpenWireStepMv) open = true;
      }
    }
    if (open) {
      t.openWire = true;
    } else {
      ++whole;
      for (uint8_t c = 0; c < view.cellsPerBoard; ++c) {
        t.packMv += s.cellMv[c];
        take(s.cellMv[c], static_cast<uint16_t>(b * kMaxCellsPerBoard + c), t.cells,
             &t.extreme[fw::app::kMaxCell], &t.at[fw::app::kMaxCell]);
      }
    }
    for (uint8_t k = 0; k < view.tempsPerBoard; ++k) {
      if (s.tempDeciK[k] == kNoReading) continue;
      take(s.tempDeciK[k], static_cast<uint16_t>(b * kMaxTempsPerBoard + k), t.temps,
           &t.extreme[fw::app::kMaxTemp], &t.at[fw::app::kMaxTemp]);
    }
  }
  t.complete = whole == view.boards.size();
  return ref;
}

// A board's cells: mostly a healthy pack from a few values (ties), sometimes one open-wire pattern.
void randomCells(std::mt19937& rng, BoardSample& s, uint8_t cells) {
  static constexpr int16_t kCommon[] = {3000, 3001, 3650, 3700, 3700, 4200};
  for (uint8_t c = 0; c < kMaxCellsPerBoard; ++c)
    s.cellMv[c] = kCommon[rng() % std::size(kCommon)];
  if (cells == 0) return;
  const uint8_t at = static_cast<uint8_t>(rng() % cells);
  switch (rng() % 10) {
    case 0:  // a cell at or about the floor
      s.cellMv[at] = static_cast<int16_t>(kCellFloorMv - 1 + static_cast<int>(rng() % 3));
      break;
    case 1:  // no reading
      s.cellMv[at] = kNoReading;
      break;
    case 2:  // a step at or about the limit to the cell above (one high, the neighbour low)
      s.cellMv[at] = 600;
      if (at + 1 < cells) s.cellMv[at + 1] = static_cast<int16_t>(600 + kOpenWireStepMv - 1 + rng() % 3);
      break;
    case 3:  // the range wider than a step, no neighbours too far apart (the range alone says nothing)
      for (uint8_t c = 0; c < cells; ++c)
        s.cellMv[c] = static_cast<int16_t>(600 + c * 600);
      break;
    case 4:  // the BQ769x2 open-wire pair in bms-sim
      s.cellMv[at] = 7400;
      if (at + 1 < cells) s.cellMv[at + 1] = 0;
      break;
    default:  // healthy
      break;
  }
}

TEST(PackViewSummarize, EqualsThePlainWalkOverRandomPacks) {
  std::mt19937 rng(20261129);
  for (int round = 0; round < 4000; ++round) {
    const auto boards = static_cast<uint16_t>(1 + rng() % fw::app::kMaxBoards);
    std::vector<BoardSample> samples(boards);
    PackView view;
    view.boards = samples;
    view.cellsPerBoard = static_cast<uint8_t>(rng() % (kMaxCellsPerBoard + 1));
    view.tempsPerBoard = static_cast<uint8_t>(rng() % (kMaxTempsPerBoard + 1));
    view.commErrors = static_cast<uint16_t>(rng() % 4 == 0 ? UINT16_MAX - rng() % 3 : rng() % 100);
    const fw::Instant scanEnd{1'000'000 + static_cast<uint32_t>(rng() % 1000)};
    for (BoardSample& s : samples) {
      const unsigned kind = rng() % 8;
      s.valid = kind != 0;
      s.last = kind == 1 ? fw::Status::Crc : kind == 2 ? fw::Status::NoResponse : fw::Status::Ok;
      s.takenAt = fw::Instant{static_cast<uint32_t>(rng() % 2'000'000)};
      randomCells(rng, s, view.cellsPerBoard);
      for (int16_t& temp : s.tempDeciK)
        temp = rng() % 6 == 0 ? kNoReading : static_cast<int16_t>(2900 + 10 * (rng() % 4));
    }
    const Reference ref = plainSummary(view, scanEnd, view.commErrors);
    fw::app::summarize(view, scanEnd);
    const PackTotals& got = view.totals;
    const PackTotals& want = ref.t;
    SCOPED_TRACE(::testing::Message()
                 << "round " << round << ", " << boards << " boards, " << int{view.cellsPerBoard}
                 << " cells, " << int{view.tempsPerBoard} << " temps");
    EXPECT_EQ(got.takenAt.us, want.takenAt.us);
    EXPECT_EQ(got.oldest.us, want.oldest.us);
    EXPECT_EQ(got.packMv, want.packMv);
    EXPECT_EQ(got.cells, want.cells);
    EXPECT_EQ(got.temps, want.temps);
    EXPECT_EQ(got.complete, want.complete);
    EXPECT_EQ(got.openWire, want.openWire);
    EXPECT_EQ(view.commErrors, ref.commErrors);
    for (int e = 0; e < 4; ++e) {  // untouched (zero) where nothing was seen, in both
      EXPECT_EQ(got.extreme[e], want.extreme[e]) << "extreme " << e;
      EXPECT_EQ(got.at[e], want.at[e]) << "place " << e;
    }
    if (::testing::Test::HasFailure()) break;
  }
}

}  // namespace
