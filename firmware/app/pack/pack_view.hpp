// PackView: the measured pack as the protection and publish tasks see it, whatever monitor produced it.
//
// A pack is a list of boards (one monitor device each: 1 for a BQ76952, BQ7690x or BQ4050, 1..64 for a
// BQ79616 chain). Each BoardSample keeps the values of the board's last *validated* measurement together
// with when it was taken and how the latest attempt ended, so every reader can tell fresh from stale:
//   boardStatus() = Valid       the last attempt validated and its values are younger than staleAfter
//                   Stale       the values validated once but are older than staleAfter
//                   CommFault   the latest attempt failed (the values, if any, are from before)
//                   NotPresent  the board never answered since start-up
// Readers must only use values of Valid boards; publishers send the others as not available (never a stale
// value as fresh). Within a Valid board two kinds of slot hold no reading: a temperature the monitor could
// not read in a scan that otherwise validated (kNoReading), and the cells beside an open sense wire
// (openWireCells()). Totals, extremes and the CAN frames leave both out.
// Units: cell voltages in mV, temperatures in 0.1 K, current in mA (positive = charging).
#pragma once

#include <cstdint>
#include <span>

#include "app/config.hpp"
#include "app/soc/soc_view.hpp"
#include "core/status.hpp"
#include "core/time.hpp"

namespace fw::app {

inline constexpr uint8_t kMaxCellsPerBoard = 16;
inline constexpr uint8_t kMaxTempsPerBoard = 4;

// Boards a pack can have in this build (FW_PACK_MAX_BOARDS, app/config.hpp).
inline constexpr uint16_t kMaxBoards = FW_PACK_MAX_BOARDS;

enum class BoardStatus : uint8_t { Valid = 0, Stale = 1, CommFault = 2, NotPresent = 3 };

// A temperature slot of a Valid board that holds no reading (the sensor's part of the scan failed).
inline constexpr int16_t kNoReading = INT16_MIN;

// Open sense wire, seen in the readings alone (the same rules for every monitor, at every tap). When the tap
// between two cells is disconnected, the device's open-wire current drains its node and the two differential
// measurements beside it go one over, one under (SLUUBY2B / SLUUCG7, Settings:Cell Open-Wire:Check Time: "an
// over-voltage or under-voltage event will be triggered on that cell or an adjacent cell"; SLUSF21, VC open
// wire detection: a current sink on every VC pin, a current source on VC0, so "the cell voltage measurement
// will drop"). At the bottom tap (VC0, pulled up) and the top tap (pulled down) there is no cell beyond it:
// only the one cell beside it reads low. So:
// - two neighbours more than kOpenWireStepMv apart are an open wire between them: a cell reads at least 0 V
//   and at most 4.5 V, above every Li-ion charge limit (the firmware's cell_ov trips at 4.25 V); in bms-sim
//   one reads about nothing and the other both cells or its input's full scale (BQ769x2: 7 400 and 0 mV for
//   two 3.7 V cells; BQ79616: 6 250 and 0 mV), and neither reading is a cell voltage;
// - a reading below kCellFloorMv is not a cell voltage either: no cell the firmware protects rests that low
//   (cell_uv trips at 2.7 V; a Li-ion or LiFePO4 cell discharged below 0.5 V is damaged and must not be
//   charged), so it is the drained node of an open tap, at any position, never a valid 0 mV.
// A node that still holds its charge (the device's check has not drained it yet) reads normal and is not
// caught (regmaps/README.md lists what is open).
inline constexpr int16_t kOpenWireStepMv = 4500;
inline constexpr int16_t kCellFloorMv = 500;
// The cells (bit c = cell c, from 0) of a board whose readings show an open sense wire beside them: a pair
// of neighbours too far apart, or one reading below the floor.
uint16_t openWireCells(const int16_t* cellMv, uint8_t cells);
// The same verdict for the `count` cells from `first` (bit 0 = cell `first`; first < cells, count < 16),
// from those cells and their two neighbours alone: what a CAN frame of three cells needs, without the
// whole board.
inline uint16_t openWireCells(const int16_t* cellMv, uint8_t cells, uint8_t first, uint8_t count) {
  const uint8_t from = first == 0 ? 0 : static_cast<uint8_t>(first - 1);
  const uint8_t to = first + count + 1 < cells ? static_cast<uint8_t>(first + count + 1) : cells;
  const uint32_t open = openWireCells(cellMv + from, static_cast<uint8_t>(to - from));
  return static_cast<uint16_t>((open >> (first - from)) & ((1U << count) - 1U));
}

// All-zero is the start-up state (no attempt yet), so arrays of samples live in .bss with no constructor.
struct BoardSample {
  Instant takenAt;  // when the values were measured (end of the validated transaction)
  Status last;      // outcome of the latest attempt to measure this board (Ok until the first attempt)
  bool valid;       // the values are from a validated measurement (possibly an old one)
  int16_t cellMv[kMaxCellsPerBoard];
  int16_t tempDeciK[kMaxTempsPerBoard];
};

// The pack at a glance, computed by the monitor once per scan (summarize()) so that protection and the
// publishers do not each walk every board: totals and extremes over the boards that validated in that scan,
// and the age of the oldest board's data (a board never measured counts from start-up).
// The four extremes share one layout (index kMaxCell..kMinTemp) so that one loop finds them and one line
// reads any of them.
enum Extreme : uint8_t { kMaxCell = 0, kMinCell = 1, kMaxTemp = 2, kMinTemp = 3 };

struct PackTotals {
  Instant takenAt;     // end of the scan these totals describe
  Instant oldest;      // oldest takenAt among all boards (Instant{0} if any board never validated)
  int32_t packMv;      // sum of the validated cells (the pack's voltage when `complete`)
  int16_t extreme[4];  // by Extreme: highest / lowest cell (mV), highest / lowest temperature (0.1 K)
  // Where each extreme is: cells as board * kMaxCellsPerBoard + cell, temperatures as
  // board * kMaxTempsPerBoard + sensor (0-based).
  uint16_t at[4];
  bool cells;     // at least one board validated in the scan (the cell extremes are meaningful)
  bool temps;     // ... and reported temperatures (the temperature extremes are meaningful)
  bool complete;  // every board validated in the scan and no open wire: packMv is the whole pack
  bool openWire;  // a validated board's readings show an open sense wire (or the monitor says so)
};

struct BalancingStatus;  // app/balancing/balancing_status.hpp

// Byte fields first: Cortex-M0+ byte loads reach only 31 bytes past the object's address.
// Pack storage (app/monitors/storage_mode.hpp), written by the monitor task only: whether the monitor is in
// storage, scanning every scanEvery scan periods (0 outside storage), the scan period in effect; staleExtra,
// added to the limits' staleAfter (protection's stale_data and what publishers call fresh); deviceAge, the
// device's own measurement interval while it may SLEEP, added to a measurement's age where that age is
// published.
#if FW_STORAGE
struct StorageView {
  bool on = false;
  uint8_t scanEvery = 0;
  Duration period{};
  Duration staleExtra{};
  Duration deviceAge{};
};
#else
struct StorageView {  // FW_STORAGE=0: never in storage, and nothing in RAM
  static constexpr bool on = false;
  static constexpr uint8_t scanEvery = 0;
  static constexpr Duration period{}, staleExtra{}, deviceAge{};
};
#endif

struct PackView {
  uint8_t cellsPerBoard = 0;  // connected cells per board
  uint8_t tempsPerBoard = 0;  // temperature sensors per board
  bool hasCurrent = false;    // pack-level values, valid with board 0's measurement
  // The paths a monitor's own protection holds off or is about to (its safety flags, alert or trip, mapped
  // bit by bit in the monitor: 1 charge, 2 discharge, as Action's bits; 0 none). Written with each scan.
  uint8_t deviceBlocks = 0;
  // The paths that are on as the device itself reports them (BQ769x2 FET Status, BQ7690x Battery Status
  // CHG/DSG; 1 charge, 2 discharge), written with each validated scan, meaningful only on a monitor that
  // reports them (hasFetStatus). Publishers say "unknown" whenever the scan behind it is not fresh.
  uint8_t devicePaths = 0;
  bool hasFetStatus = false;
  // The monitor is set up and scanning (written by the monitor task only). Protection takes the fault line
  // (ALERT/nFAULT) as a fault only while it is: during bring-up and recovery the line is expected to be
  // asserted (BQ79616 devices leave reset with faults latched; a BQ769x2 asserts ALERT until configured).
  bool monitorRunning = false;
  // The monitor's first bring-up is under way (written by the monitor task only: true from its start until
  // the first scan's result). Until then, and while the clock is before firstDataDue (MonitorTask:
  // Device::firstDataBound() from power-up), nothing has been measured on purpose, not lost: protection
  // leaves stale_data and comm_loss alone and the monitor reports no failed scan periods (inStartupGrace()).
  // Past the bound a pack never measured is stale, counted from power-up.
  bool startupGrace = false;
  // The state of charge (app/soc/soc_view.hpp), set by the monitor; basis Unknown (zero, the state the images
  // start from) means none, and the StateOfCharge signals go out not available. Empty in FW_SOC=0 builds.
  [[no_unique_address]] SocView soc{};
  // Board measurements that failed since start-up, counted by summarize() (a scan that fails on n boards
  // counts n), saturating at 65535; published as ProtectionEvent.CommErrors. Not counted in builds that do
  // not publish it (FW_PUBLISH_LEVEL 0).
  uint16_t commErrors = 0;
  int32_t currentMa = 0;
  Instant firstDataDue{};  // see startupGrace
  std::span<const BoardSample> boards{};
  // Optional: the monitor's raw cell codes, kMaxCellsPerBoard per board in board order (BQ79616: 190.73 uV
  // LSB), for the TI-compatible CAN layout, which carries raw codes. Null when the monitor has none.
  const int16_t* rawCells = nullptr;
  // Optional: the pack's balancing (app/balancing/balancing_status.hpp), published as BalancingStatus. Null
  // on an image that does not balance (the BQ4050's gauge balances on its own).
  const BalancingStatus* balancing = nullptr;
  PackTotals totals{};
  [[no_unique_address]] StorageView storage{};

  uint16_t boardCount() const { return kMaxBoards == 1 ? 1 : static_cast<uint16_t>(boards.size()); }
  bool inStartupGrace(Instant now) const { return startupGrace && isBefore(now, firstDataDue); }
};

// Recomputes view.totals from the boards whose last attempt validated (without the slots that hold no
// reading), and counts the boards whose last attempt failed into view.commErrors; `scanEnd` is when the scan
// ended. Monitors call it exactly once per scan, after recording every board's attempt; a monitor that
// learns of an open sense line otherwise (the BQ4050's refused cell word) sets totals.openWire after it.
void summarize(PackView& view, Instant scanEnd);

constexpr BoardStatus boardStatus(const BoardSample& b, Instant now, Duration staleAfter) {
  if (!b.valid) return BoardStatus::NotPresent;
  if (b.last != Status::Ok) return BoardStatus::CommFault;
  return elapsed(b.takenAt, now) > staleAfter ? BoardStatus::Stale : BoardStatus::Valid;
}

}  // namespace fw::app
