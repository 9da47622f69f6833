#include "app/pack/pack_view.hpp"

#include "app/publish/publish_status.hpp"

namespace fw::app {

namespace {

// Folds `n` values into an extremes pair (ext[0] max, ext[1] min) and their places (at[]), numbering them
// from `first`, and returns their sum. kNoReading values are left out. One function for cells and
// temperatures.
int32_t fold(int16_t* ext, uint16_t* at, bool& seen, const int16_t* values, uint8_t n, uint16_t first) {
  int32_t sum = 0;
  for (uint8_t k = 0; k < n; ++k, ++first) {
    const int16_t v = values[k];
    if (v == kNoReading) continue;
    sum += v;
    if (!seen || v > ext[0]) ext[0] = v, at[0] = first;
    if (!seen || v < ext[1]) ext[1] = v, at[1] = first;
    seen = true;
  }
  return sum;
}

// A board's readings (its cells, or its temperatures) in one pass: their sum and their highest and lowest,
// without places (a fold of every board's cells with places, and the open-wire walk beside it, were 17 % of
// the 64-device BQ79616 image's busy cycles, twin profile).
struct ReadingRange {
  int32_t sum;
  int32_t max;
  int32_t min;
};
// Scalars in the loop and its own function: with the struct's members in the loop, or inlined into
// summarize(), GCC kept the three on the stack (a load and a store each a cell).
[[gnu::noinline]] ReadingRange readingRange(const int16_t* reading, uint8_t count) {
  int32_t sum = 0;
  int32_t max = INT16_MIN;
  int32_t min = INT16_MAX;
  if (count != 0) {  // the loop test at the bottom: 14 cycles a reading, 18 with it at the top
    const int16_t* const end = reading + count;
    do {
      const int32_t v = *reading;
      sum += v;
      if (v > max) max = v;
      if (v < min) min = v;
    } while (++reading != end);
  }
  return {sum, max, min};
}

// Folds a board's cells into the totals unless they show an open wire (openWireCells()); true if folded.
bool foldCells(PackTotals& t, const int16_t* cellMv, uint8_t cells, uint16_t board) {
  const auto first = static_cast<uint16_t>(board * kMaxCellsPerBoard);
  if constexpr (kMaxBoards == 1) {
    // One board: a walk of each kind costs little, and the code is smallest (the L1306 images).
    if (openWireCells(cellMv, cells) != 0) return false;
    t.packMv += fold(&t.extreme[kMaxCell], &t.at[kMaxCell], t.cells, cellMv, cells, first);
    return true;
  } else {
    // openWireCells() finds one only where a cell reads below kCellFloorMv or two neighbours are more than
    // kOpenWireStepMv apart; no two cells are further apart than the board's highest and lowest, so a board
    // whose range shows neither is clear without the walk over its neighbours. (A kNoReading cell is below
    // the floor: such a board is never folded, as before; a board of no cells has the empty range, clear.)
    const ReadingRange r = readingRange(cellMv, cells);
    if (r.min < kCellFloorMv || (r.max - r.min > kOpenWireStepMv && openWireCells(cellMv, cells) != 0))
      return false;
    t.packMv += r.sum;
    // Only a board that holds a new extreme of the pack is walked again, by the fold that finds where.
    if (!t.cells || r.max > t.extreme[kMaxCell] || r.min < t.extreme[kMinCell])
      fold(&t.extreme[kMaxCell], &t.at[kMaxCell], t.cells, cellMv, cells, first);
    return true;
  }
}

// Folds a board's temperatures into the totals.
void foldTemps(PackTotals& t, const int16_t* tempDeciK, uint8_t temps, uint16_t board) {
  if constexpr (kMaxBoards > 1) {
    // As with the cells, only a board that could hold a new extreme is folded: a kNoReading slot reads as
    // the lowest value, so a board with one is always folded (the fold leaves it out).
    const ReadingRange r = readingRange(tempDeciK, temps);
    if (t.temps && r.max <= t.extreme[kMaxTemp] && r.min >= t.extreme[kMinTemp]) return;
  }
  fold(&t.extreme[kMaxTemp], &t.at[kMaxTemp], t.temps, tempDeciK, temps,
       static_cast<uint16_t>(board * kMaxTempsPerBoard));
}

}  // namespace

uint16_t openWireCells(const int16_t* cellMv, uint8_t cells) {
  uint32_t open = 0;
  for (uint32_t pair = 3; cells-- != 0; pair <<= 1, ++cellMv) {
    if (cellMv[0] < kCellFloorMv) open |= pair & (pair >> 1);  // this cell alone (bit 0 of the pair)
    if (cells == 0) break;                                     // the last cell has no neighbour above
    const int32_t step = cellMv[1] - cellMv[0];
    if (step > kOpenWireStepMv || step < -kOpenWireStepMv) open |= pair;
  }
  return static_cast<uint16_t>(open);
}

void summarize(PackView& view, Instant scanEnd) {
  PackTotals& t = view.totals;
  t = PackTotals{};
  t.takenAt = scanEnd;
  t.oldest = scanEnd;
  uint16_t whole = 0;  // boards whose cells validated with no open wire
  const uint8_t cells = view.cellsPerBoard;
  for (uint16_t b = 0; b < view.boardCount(); ++b) {
    const BoardSample& s = view.boards[b];
    if (!s.valid) {
      t.oldest = Instant{};  // never measured: as old as the firmware
    } else if (isBefore(s.takenAt, t.oldest) && t.oldest.us != 0) {
      t.oldest = s.takenAt;
    }
    if (s.last != Status::Ok) {
      if (kCoreMessages && view.commErrors != UINT16_MAX) ++view.commErrors;
      continue;
    }
    if (!s.valid) continue;
    // A board with an open sense wire keeps its cells out of the extremes and the cell limits: two of its
    // readings are not cell voltages, and open_wire, which opens both paths, stands in for its limits.
    if (foldCells(t, s.cellMv, cells, b)) {
      ++whole;
    } else {
      t.openWire = true;
    }
    foldTemps(t, s.tempDeciK, view.tempsPerBoard, b);
  }
  t.complete = whole == view.boardCount();
}

}  // namespace fw::app
