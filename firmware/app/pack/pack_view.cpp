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
    if (openWireCells(s.cellMv, view.cellsPerBoard) != 0) {
      t.openWire = true;
    } else {
      ++whole;
      t.packMv += fold(&t.extreme[kMaxCell], &t.at[kMaxCell], t.cells, s.cellMv, view.cellsPerBoard,
                       static_cast<uint16_t>(b * kMaxCellsPerBoard));
    }
    fold(&t.extreme[kMaxTemp], &t.at[kMaxTemp], t.temps, s.tempDeciK, view.tempsPerBoard,
         static_cast<uint16_t>(b * kMaxTempsPerBoard));
  }
  t.complete = whole == view.boardCount();
}

}  // namespace fw::app
