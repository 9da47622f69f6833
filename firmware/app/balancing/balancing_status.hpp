// BalancingStatus: what the pack's balancing is, as the publishers send it (BalancingStatus in
// firmware/app/can/bms.yaml). The monitor task writes it, the publisher reads it (PackView::balancing).
// cells[] holds only what a device confirmed (BQ769x2/BQ7690x: CB_ACTIVE_CELLS read back; BQ79616: BAL_STAT
// running, not paused, not aborted, for the timers last written); a board whose state is not known (its link
// failed) shows none. Times count while a board's confirmation stands.
#pragma once

#include <cstdint>

#include "app/balancing/balancing_policy.hpp"
#include "app/pack/pack_view.hpp"
#include "core/time.hpp"

namespace fw::app {

struct BalancingStatus {  // all-zero is the start-up state (Zeroed blocks): Auto, NoData, no cells
  uint8_t modeCode;       // BalancingMode XOR Auto, as the policy keeps it, so zero is Auto
  BalancingState state;
  uint16_t cells[kMaxBoards];    // bit c = cell c + 1, as the device confirmed it
  uint32_t seconds[kMaxBoards];  // time with any confirmed cell since start-up, whole seconds
  uint32_t us[kMaxBoards];       // ... and the part of a second not counted yet

  BalancingMode mode() const { return static_cast<BalancingMode>(modeCode ^ kAuto); }
  void setMode(BalancingMode m) { modeCode = static_cast<uint8_t>(static_cast<uint8_t>(m) ^ kAuto); }
  static constexpr uint8_t kAuto = static_cast<uint8_t>(BalancingMode::Auto);

  // Adds `dt` to every board that has a confirmed cell (called once per check, dt since the last one).
  void account(uint16_t boards, Duration dt) {
    for (uint16_t b = 0; b < boards; ++b) {
      if (cells[b] == 0) continue;
      us[b] += dt.us;
      while (us[b] >= 1000000U) {
        us[b] -= 1000000U;
        ++seconds[b];
      }
    }
  }
};

}  // namespace fw::app
