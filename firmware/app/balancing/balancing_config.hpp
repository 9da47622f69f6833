// The balancing parameters of a pack: one constexpr table, in integer mV, mA, 0.1 K and time. Li-ion defaults
// until the pack file (issue 29) generates this table; README.md in this folder says why each value is what
// it is and compares it with TI's automatic balancing, LibreSolar and foxBMS.
#pragma once

#include <cstdint>

#include "core/time.hpp"

namespace fw::app {

struct BalancingConfig {
  // A balancing episode starts when the highest cell is at least startDeltaMv above the lowest, and ends
  // when the pack is within stopDeltaMv (the stop threshold). Inside an episode a cell balances while it is
  // more than stopDeltaMv above the lowest; once stopped it starts again only from stopDeltaMv +
  // cellHysteresisMv, so a reading that wobbles by a millivolt at the threshold does not switch it.
  int16_t startDeltaMv = 20;
  int16_t stopDeltaMv = 10;
  int16_t cellHysteresisMv = 5;
  // No balancing while the lowest cell is below this (a low pack keeps its charge).
  int16_t minCellMv = 3600;
  // Charging: current >= chargeCurrentMa. At rest: |current| < restCurrentMa for restTime. Anything else
  // (a discharge, or a rest not long enough yet) does not balance.
  int32_t chargeCurrentMa = 100;
  int32_t restCurrentMa = 50;
  Duration restTime = s(60);
  // Temperature limits (0.1 K): cell sensors within [minCellTempDeciK, maxCellTempDeciK], the monitor's die
  // below maxDieTempDeciK (each inside the device's own balancing limits, which stay the backstop).
  int16_t minCellTempDeciK = 2732;  // 0 degC
  int16_t maxCellTempDeciK = 3182;  // 45 degC
  int16_t maxDieTempDeciK = 3382;   // 65 degC
  // The set of balanced cells changes at most this often (a stop is never delayed).
  Duration minDwell = s(2);
  // After the device refused what was asked (read-back different, INVALID_CBCONF), nothing is asked for
  // this long.
  Duration refusedBackoff = s(10);
};

inline constexpr BalancingConfig kDefaultBalancing{};

}  // namespace fw::app
