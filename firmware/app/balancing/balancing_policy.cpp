#include "app/balancing/balancing_policy.hpp"

namespace fw::app {

Status BalancingPolicy::setMode(BalancingMode mode, uint16_t board, uint16_t mask, uint16_t boards,
                                uint8_t cells) {
  const bool forced = mode == BalancingMode::Forced;
  if (mode > BalancingMode::Forced || (forced && (board >= boards || !maskAllowed(mask, cells, rules_))))
    return Status::InvalidArgument;
  State& st = *state_;
  st.modeCode = static_cast<uint8_t>(static_cast<uint8_t>(mode) ^ kAutoCode);
  st.forcedBoard = static_cast<uint8_t>(forced ? board : 0);
  st.forcedMask = forced ? mask : 0;
  st.episode = false;  // Auto starts from the thresholds again
  return Status::Ok;
}

void BalancingPolicy::refused(Instant now) {
  state_->backingOff = true;
  state_->backoffUntil = now + config_.refusedBackoff;
}

// The first condition that stops every board's balancing, or Balancing when none does.
BalancingState BalancingPolicy::blocked(const PackView& view, FaultMask faults) {
  State& st = *state_;
  const BalancingMode m = mode();
  if (m == BalancingMode::Off) return BalancingState::Off;
  if (faults != 0 || view.deviceBlocks != 0) return BalancingState::Fault;
  const PackTotals& t = view.totals;
  // Every board validated in this scan with no open wire: otherwise the lowest cell of the pack is not known.
  if (!t.complete || !t.cells) return BalancingState::NoData;
  for (uint16_t b = 0; b < view.boardCount(); ++b) {
    const int16_t* temps = view.boards[b].tempDeciK;
    for (uint8_t k = 0; k < view.tempsPerBoard; ++k) {
      const int16_t v = temps[k];
      const bool die = ((rules_.dieSensors >> k) & 1U) != 0;
      const bool out =
          die ? v > config_.maxDieTempDeciK : v < config_.minCellTempDeciK || v > config_.maxCellTempDeciK;
      if (v == kNoReading || out) return BalancingState::Temperature;
    }
  }
  if (t.extreme[kMinCell] < config_.minCellMv) return BalancingState::LowVoltage;
  if (st.backingOff) return BalancingState::Refused;
  if (m == BalancingMode::Forced) return BalancingState::Balancing;
  // Charging, or at rest long enough. Without a current sensor the pack counts as at rest.
  const int32_t i = view.currentMa;
  const bool charging = view.hasCurrent && i >= config_.chargeCurrentMa;
  const bool rested = !view.hasCurrent || st.rested;
  return charging || rested ? BalancingState::Balancing : BalancingState::NotResting;
}

void BalancingPolicy::decide(const PackView& view, FaultMask faults, Instant now, std::span<uint16_t> want) {
  State& st = *state_;
  // The rest timer runs whatever else holds balancing back.
  const int32_t i = view.currentMa;
  if (!view.hasCurrent || i >= config_.restCurrentMa || i <= -config_.restCurrentMa) {
    st.resting = st.rested = false;
  } else if (!st.resting) {
    st.resting = true;
    st.restSince = now;
  }
  if (st.resting && !st.rested) st.rested = elapsed(st.restSince, now) >= config_.restTime;
  // The back-off ends by the clock whatever else holds balancing back (a deadline compared half a wrap
  // later would look ahead again).
  if (st.backingOff && isDue(st.backoffUntil, now)) st.backingOff = false;
  const uint16_t boards = view.boardCount();
  const BalancingState why = blocked(view, faults);
  st.state = why;
  // Held back: nothing balances. An Auto episode goes on after the hold (README: it ends at the stop delta
  // only): a charge that stops and the rest that follows would otherwise end it with the spread anywhere
  // between the two thresholds, too small to start a new one. Forced: the forced board's mask, nothing
  // elsewhere.
  const bool held = why != BalancingState::Balancing;
  if (held || mode() == BalancingMode::Forced) {
    const uint16_t mask = held ? 0 : st.forcedMask;
    for (uint16_t b = 0; b < boards; ++b)
      want[b] = b == st.forcedBoard ? mask : 0;
    return;
  }
  const PackTotals& t = view.totals;
  const int16_t lowest = t.extreme[kMinCell];
  const int32_t spread = t.extreme[kMaxCell] - lowest;
  if (!st.episode && spread >= config_.startDeltaMv) st.episode = true;
  if (st.episode && spread <= config_.stopDeltaMv) st.episode = false;
  bool any = false;
  for (uint16_t b = 0; b < boards; ++b) {
    if (!st.episode) want[b] = st.done[b] = 0;
    any = any || want[b] != 0;
  }
  if (!st.episode) {
    st.state = BalancingState::Balanced;
    return;
  }
  // The set of cells holds for minDwell once something balances (the episode's first set goes out at once).
  if (any && !st.settled) {
    if (!isDue(st.changedAt + config_.minDwell, now)) return;
    st.settled = true;
  }
  bool changed = false;
  any = false;
  for (uint16_t b = 0; b < boards; ++b) {
    const uint16_t m = select(view.boards[b], view.cellsPerBoard, lowest, want[b], st.done[b]);
    changed = changed || m != want[b];
    any = any || m != 0;
    want[b] = m;
  }
  if (changed) st.changedAt = now, st.settled = false;
  if (!any)
    st.state = BalancingState::Balanced;  // every cell above the stop threshold sits in the hysteresis
}

// The cells of one board to balance: those more than the stop threshold above the lowest cell and not done (a
// cell is done once it came down to the stop threshold, until it is cellHysteresisMv above it again), highest
// first, a cell already on ranked cellHysteresisMv higher so two close cells do not take turns; at most
// maxCells, and no neighbours unless the device allows them. A cell left out for a higher one or a neighbour
// stays a candidate.
uint16_t BalancingPolicy::select(const BoardSample& board, uint8_t cells, int16_t lowest, uint16_t on,
                                 uint16_t& done) const {
  const int32_t stop = config_.stopDeltaMv;
  const int32_t hysteresis = config_.cellHysteresisMv;
  for (uint8_t c = 0; c < cells; ++c) {
    const auto bit = static_cast<uint16_t>(1U << c);
    const int32_t excess = board.cellMv[c] - lowest;
    if (excess <= stop) done = static_cast<uint16_t>(done | bit);
    if (excess >= stop + hysteresis) done = static_cast<uint16_t>(done & ~bit);
  }
  uint16_t taken = done;  // done cells, chosen cells and, where neighbours are not allowed, theirs
  uint16_t chosen = 0;
  for (uint8_t n = 0; n < rules_.maxCells; ++n) {
    int32_t best = 0;
    uint16_t bestBit = 0;
    for (uint8_t c = 0; c < cells; ++c) {
      const auto bit = static_cast<uint16_t>(1U << c);
      if ((taken & bit) != 0) continue;
      const int32_t rank = board.cellMv[c] - lowest + ((on & bit) != 0 ? hysteresis : 0);
      if (rank > best) best = rank, bestBit = bit;
    }
    if (bestBit == 0) break;
    chosen = static_cast<uint16_t>(chosen | bestBit);
    taken = static_cast<uint16_t>(taken | bestBit |
                                  (rules_.adjacentAllowed ? 0U : (bestBit << 1) | (bestBit >> 1)));
  }
  return chosen;
}

}  // namespace fw::app
