// One row of a limit table: the form the pack generator (regmapgen pack) writes a pack file's limits in
// (gen/packs/<name>.hpp kLimitRows), which app/protection/default_limits.hpp turns into the ProtectionConfig.
#pragma once

#include <cstdint>

#include "app/protection/protection.hpp"

namespace fw::app {

// The fault, its thresholds (mV, mA, 0.1 K; 0/1 for the flag rules), the trip and recovery counts
// (evaluations, one per scan), the action, whether it latches on its first trip, and the trip count that
// latches it with the decay (s) that forgives one (Rule::latchTrips, tripDecayS).
struct LimitRow {
  FaultId fault;
  int32_t trip;
  int32_t clear;
  uint8_t debounce;
  uint8_t recover;
  Action action;
  bool latch;
  uint8_t latchTrips = 0;
  uint8_t tripDecayS = 0;
};

inline constexpr int32_t kDeciKelvinAtZeroCelsius = 2732;
constexpr int32_t degC(int32_t c) {
  return kDeciKelvinAtZeroCelsius + 10 * c;
}

}  // namespace fw::app
