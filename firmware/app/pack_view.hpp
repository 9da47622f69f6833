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

// All-zero is the start-up state (no attempt yet), so arrays of samples live in .bss with no constructor.
struct BoardSample {
  Instant takenAt;  // when the values were measured (end of the validated transaction)
  Status last;      // outcome of the latest attempt to measure this board (meaningful once attempted)
  bool attempted;   // the monitor has tried to measure this board at least once
  bool valid;       // the values are from a validated measurement (possibly an old one)
  int16_t cellMv[kMaxCellsPerBoard];
  int16_t tempDeciK[kMaxTempsPerBoard];
};

// The pack at a glance, computed by the monitor once per scan (summarize()) so that protection and the
// publishers do not each walk every board: totals and extremes over the boards that validated in that scan,
// and the age of the oldest board's data (a board never measured counts from start-up).
struct PackTotals {
  Instant takenAt;  // end of the scan these totals describe
  Instant oldest;   // oldest takenAt among all boards (Instant{0} if any board never validated)
  bool cells;       // at least one board validated in the scan
  bool temps;
  int32_t packMv;  // sum of the validated cells
  int16_t maxCell, minCell, maxTemp, minTemp;
  uint16_t maxCellAt, minCellAt;  // board * kMaxCellsPerBoard + cell (0-based)
  uint16_t maxTempAt, minTempAt;  // board * kMaxTempsPerBoard + sensor (0-based)
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
  PackTotals totals{};
};

// Recomputes view.totals from the boards whose last attempt validated; `scanEnd` is when the scan ended.
void summarize(PackView& view, Instant scanEnd);

constexpr BoardStatus boardStatus(const BoardSample& b, Instant now, Duration staleAfter) {
  if (!b.attempted || !b.valid) return BoardStatus::NotPresent;
  if (b.last != Status::Ok) return BoardStatus::CommFault;
  return elapsed(b.takenAt, now) > staleAfter ? BoardStatus::Stale : BoardStatus::Valid;
}

}  // namespace fw::app
