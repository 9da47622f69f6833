// The state-of-charge parameters of a pack: capacity, the voltage resets, rest, and the cell's open-circuit
// voltage table. One constexpr table per pack, generated from its pack file (firmware/app/packs/README.md).
#pragma once

#include <cstdint>

#include "core/time.hpp"

namespace fw::app {

inline constexpr uint8_t kOcvPoints = 11;  // 0, 10, ..., 100 %

struct SocConfig {
  uint32_t capacityMah = 0;
  // Highest cell at or above fullCellMv while not discharging: 100 %. Lowest cell at or below emptyCellMv
  // while not charging: 0 %.
  int16_t fullCellMv = 0;
  int16_t emptyCellMv = 0;
  // At rest: |current| below restCurrentMa for restTime; then (and every restTime while it lasts) the
  // open-circuit voltage corrects the count.
  int32_t restCurrentMa = 0;
  Duration restTime{};
  // A correction only where the table's 10 % step around the voltage rises at least this much: on a flat part
  // of the curve (LFP between 20 and 90 %) the voltage says too little about the charge.
  int16_t ocvMinStepMv = 20;
  int16_t ocvMv[kOcvPoints] = {};
};

}  // namespace fw::app
