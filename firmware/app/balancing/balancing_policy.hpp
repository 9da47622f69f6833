// BalancingPolicy: which cells of which board to balance, the same for every monitor family.
//
// Once per scan (decide()) it turns the measured pack into one wanted mask per board (bit c = cell c + 1):
//   - never while a protection fault or the monitor's own fault is active, while any board's last scan did
//     not validate (or shows an open sense wire), while a cell or die temperature is outside its limit or has
//     no reading, or while the lowest cell is below minCellMv: then every mask is 0 at once;
//   - Auto: only while charging or at rest (BalancingConfig), a monitor without a current sensor (BQ79616)
//     counting as at rest; an episode starts at startDeltaMv of spread and ends at stopDeltaMv; inside it the
//     cells more than stopDeltaMv above the pack's lowest cell balance (a cell that came down to the stop
//     threshold is done, and starts again only cellHysteresisMv above it), highest first, at most the
//     device's maxCells per board and never two neighbours where the device refuses or overheats them
//     (BalancingRules); the set changes at most every minDwell, a stop at once;
//   - Forced (service): one board's mask as given, under the same safety conditions (faults, data,
//     temperatures, minimum voltage) but none of Auto's (spread, charge or rest);
//   - Off: nothing.
// setMode() is the command interface's entry (BalancingMode in firmware/app/can/bms.yaml). refused() is the
// monitor's report that the device did not take a mask: nothing is asked for refusedBackoff.
// What the device confirmed is not the policy's business: the monitor publishes it (BalancingStatus).
// Thread mode only (the monitor task calls decide(); the command task setMode(): cooperative, never at once).
#pragma once

#include <cstdint>
#include <span>

#include "app/balancing/balancing_config.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/protection.hpp"
#include "core/bits.hpp"
#include "core/status.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"

namespace fw::app {

enum class BalancingMode : uint8_t { Off = 0, Auto = 1, Forced = 2 };  // bms.yaml BalancingMode.Mode

// Why the pack balances or not (BalancingStatus.State in bms.yaml), the first reason that applies. Zero is
// NoData, what stands before the first scan (the all-zero start-up state says so).
enum class BalancingState : uint8_t {
  NoData = 0,       // a board's last scan did not validate, or shows an open sense wire (or none ran yet)
  Balanced = 1,     // auto: no episode (the spread is below the start threshold, or fell to the stop one)
  Off = 2,          // mode off
  Fault = 3,        // a protection fault, or the monitor's own, is active
  Balancing = 4,    // a cell is wanted balancing
  Temperature = 5,  // a cell or die temperature is outside its limit or has no reading
  LowVoltage = 6,   // the lowest cell is below minCellMv
  NotResting = 7,   // auto: discharging, or not at rest for restTime yet
  Refused = 8,      // the device refused the last mask: backing off
};

// What a monitor family allows (each value cites its TI source where the family's app builds it).
struct BalancingRules {
  uint8_t maxCells;      // cells one board balances at once
  bool adjacentAllowed;  // two neighbouring cells at once
  uint8_t dieSensors;    // PackView temperature slots (bit s = slot s) that are die temperatures
};

// The masks a set of rules allows on a board of `cells` cells (bit c = cell c + 1).
constexpr bool maskAllowed(uint16_t mask, uint8_t cells, const BalancingRules& rules) {
  if (cells < 16 && (mask >> cells) != 0) return false;
  if (!rules.adjacentAllowed && (mask & (mask >> 1)) != 0) return false;
  return countBits(mask) <= rules.maxCells;
}

class BalancingPolicy {
 public:
  BalancingPolicy(const BalancingConfig& config, const BalancingRules& rules)
      : config_(config), rules_(rules) {}

  // Off, Auto, or Forced with `mask` on `board` of a pack of `boards` boards of `cells` cells.
  // InvalidArgument (nothing changes) for a mode out of range, a board the pack does not have, or a mask the
  // device does not allow. The next decide() applies it.
  Status setMode(BalancingMode mode, uint16_t board, uint16_t mask, uint16_t boards, uint8_t cells);

  // Once per scan, after protection evaluated it: `faults` is protection's active set. Writes one mask per
  // board of the view into `want` (want.size() >= the view's boards).
  void decide(const PackView& view, FaultMask faults, Instant now, std::span<uint16_t> want);
  // The device did not take what was asked: every mask is 0 for refusedBackoff.
  void refused(Instant now);

  BalancingMode mode() const { return static_cast<BalancingMode>(state_->modeCode ^ kAutoCode); }
  BalancingState state() const { return state_->state; }
  const BalancingRules& rules() const { return rules_; }

 private:
  BalancingState blocked(const PackView& view, FaultMask faults);
  uint16_t select(const BoardSample& board, uint8_t cells, int16_t lowest, uint16_t on, uint16_t& done) const;

  // Zero at construction, which is Auto: the mode is kept XOR Auto, so the start-up mode costs no code.
  static constexpr uint8_t kAutoCode = static_cast<uint8_t>(BalancingMode::Auto);
  struct State {
    uint8_t modeCode;  // BalancingMode ^ kAutoCode
    BalancingState state;
    bool episode;
    bool resting;  // restSince is meaningful
    // The rest time and the dwell, once reached, are kept as flags: Instant wraps after 71.6 minutes, and a
    // balancing set can stand longer than that (a 2.5 Ah cell loses about 16 mV an hour).
    bool rested;   // resting for restTime
    bool settled;  // the set of cells has stood for minDwell
    bool backingOff;
    uint8_t forcedBoard;
    uint16_t forcedMask;
    Instant restSince;
    Instant changedAt;
    Instant backoffUntil;
    uint16_t done[kMaxBoards];  // per board, the cells that came down to the stop threshold this episode
  };
  const BalancingConfig& config_;
  BalancingRules rules_;
  Zeroed<State> state_;
};

}  // namespace fw::app
