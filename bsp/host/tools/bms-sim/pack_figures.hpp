// Shared helpers for the image simulations: pack figures from the firmware's PackView and publish status.
#pragma once

#include <algorithm>

#include "app/pack_view.hpp"
#include "app/publish_status.hpp"
#include "image_sim.hpp"

namespace bmssim {

inline void fillPackFigures(SimFigures& f, const fw::app::PackView& view, const fw::app::PublishStatus& st,
                            fw::Instant now, fw::Duration staleAfter) {
  f.boards = static_cast<int>(view.boards.size());
  f.validBoards = 0;
  bool any = false;
  for (const auto& b : view.boards) {
    if (fw::app::boardStatus(b, now, staleAfter) != fw::app::BoardStatus::Valid) continue;
    ++f.validBoards;
    for (uint8_t c = 0; c < view.cellsPerBoard; ++c) {
      f.minCellMv = any ? std::min<int>(f.minCellMv, b.cellMv[c]) : b.cellMv[c];
      f.maxCellMv = any ? std::max<int>(f.maxCellMv, b.cellMv[c]) : b.cellMv[c];
      any = true;
    }
  }
  f.currentMa = view.hasCurrent ? view.currentMa : 0;
  f.chargeOn = st.chargeOn;
  f.dischargeOn = st.dischargeOn;
  f.faultOutput = st.faultOutput;
  f.activeFaults = st.active;
}

}  // namespace bmssim
