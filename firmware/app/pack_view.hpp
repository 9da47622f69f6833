// PackView: the measured pack as the protection and publish tasks see it, whatever monitor produced it.
//
// A pack is a list of boards (one monitor device each: 1 for a BQ76952, BQ7690x or BQ4050, 1..64 for a
// BQ79616 chain). Each BoardSample keeps the values of the board's last *validated* measurement together
// with when it was taken and how the latest attempt ended, so every reader can tell fresh from stale:
//   boardStatus() = Valid       the last attempt validated and its values are younger than staleAfter
//                   Stale       the values validated once but are older than staleAfter
//                   CommFault   the latest attempt failed (the values, if any, are from before)
//                   NotPresent  the board never answered since start-up
// Readers must only use values of Valid boards; publishers zero the others (never a stale value as fresh).
// Units: cell voltages in mV, temperatures in 0.1 K, current in mA (positive = charging).
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/time.hpp"

namespace fw::app {

inline constexpr uint8_t kMaxCellsPerBoard = 16;
inline constexpr uint8_t kMaxTempsPerBoard = 4;

enum class BoardStatus : uint8_t { Valid = 0, Stale = 1, CommFault = 2, NotPresent = 3 };

struct BoardSample {
  Instant takenAt{};               // when the values were measured (end of the validated transaction)
  Status last = Status::NotReady;  // outcome of the latest attempt to measure this board
  bool valid = false;              // the values are from a validated measurement (possibly an old one)
  int16_t cellMv[kMaxCellsPerBoard]{};
  int16_t tempDeciK[kMaxTempsPerBoard]{};
};

struct PackView {
  std::span<const BoardSample> boards{};
  uint8_t cellsPerBoard = 0;  // connected cells per board
  uint8_t tempsPerBoard = 0;  // temperature sensors per board
  bool hasCurrent = false;    // pack-level values, valid with board 0's measurement
  int32_t currentMa = 0;
  uint8_t stateOfCharge = 255;  // % from a gas gauge; 255 = unknown
  bool deviceFault = false;     // a monitor reports a tripped protection of its own
  // Optional: the monitor's raw cell codes, kMaxCellsPerBoard per board in board order (BQ79616: 190.73 uV
  // LSB), for the TI-compatible CAN layout, which carries raw codes. Null when the monitor has none.
  const int16_t* rawCells = nullptr;
};

constexpr BoardStatus boardStatus(const BoardSample& b, Instant now, Duration staleAfter) {
  if (b.last != Status::Ok) return b.valid ? BoardStatus::CommFault : BoardStatus::NotPresent;
  if (!b.valid) return BoardStatus::NotPresent;
  return elapsed(b.takenAt, now) > staleAfter ? BoardStatus::Stale : BoardStatus::Valid;
}

}  // namespace fw::app
