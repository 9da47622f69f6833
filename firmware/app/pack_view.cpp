#include "app/pack_view.hpp"

namespace fw::app {

void summarize(PackView& view, Instant scanEnd) {
  PackTotals t{};
  t.takenAt = scanEnd;
  t.oldest = scanEnd;
  for (uint16_t b = 0; b < view.boards.size(); ++b) {
    const BoardSample& s = view.boards[b];
    if (!s.valid) {
      t.oldest = Instant{};  // never measured: as old as the firmware
    } else if (isBefore(s.takenAt, t.oldest) && t.oldest.us != 0) {
      t.oldest = s.takenAt;
    }
    if (!s.attempted || s.last != Status::Ok || !s.valid) continue;
    for (uint8_t c = 0; c < view.cellsPerBoard; ++c) {
      const int16_t v = s.cellMv[c];
      const auto at = static_cast<uint16_t>(b * kMaxCellsPerBoard + c);
      t.packMv += v;
      if (!t.cells || v > t.maxCell) t.maxCell = v, t.maxCellAt = at;
      if (!t.cells || v < t.minCell) t.minCell = v, t.minCellAt = at;
      t.cells = true;
    }
    for (uint8_t k = 0; k < view.tempsPerBoard; ++k) {
      const int16_t v = s.tempDeciK[k];
      const auto at = static_cast<uint16_t>(b * kMaxTempsPerBoard + k);
      if (!t.temps || v > t.maxTemp) t.maxTemp = v, t.maxTempAt = at;
      if (!t.temps || v < t.minTemp) t.minTemp = v, t.minTempAt = at;
      t.temps = true;
    }
  }
  view.totals = t;
}

}  // namespace fw::app
