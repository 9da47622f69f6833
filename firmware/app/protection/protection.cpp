#include "app/protection/protection.hpp"

#include "core/bits.hpp"

namespace fw::app {
// The six value limits come first in FaultId order, alternating upper and lower limits; cells and
// temperatures line up with PackTotals::extreme (cells at 0, 1, temperatures at 2, 3), so one loop handles
// them all. The charge-side temperature limits (10, 11) read the same extremes as 4 and 5.
static_assert(static_cast<uint8_t>(FaultId::CellOvervoltage) == 0 &&
              static_cast<uint8_t>(FaultId::CellUndervoltage) == 1 &&
              static_cast<uint8_t>(FaultId::ChargeOvercurrent) == 2 &&
              static_cast<uint8_t>(FaultId::DischargeOvercurrent) == 3 &&
              static_cast<uint8_t>(FaultId::OvertempDischarge) == 4 &&
              static_cast<uint8_t>(FaultId::UndertempDischarge) == 5 &&
              static_cast<uint8_t>(FaultId::OvertempCharge) == 10 &&
              static_cast<uint8_t>(FaultId::UndertempCharge) == 11);
static_assert(kMaxCell == 0 && kMinCell == 1 && kMaxTemp == 4 - 2 && kMinTemp == 5 - 2);

ProtectionState Protection::evaluate(const ProtectionInputs& in, Instant now) {
  ProtectionState out;

  if (in.fresh) {
    state_->failedScans = 0;
  } else if (in.scanFailed && state_->failedScans < 0xFF) {
    ++state_->failedScans;
  }
  if (in.fresh || in.scanFailed)
    state_->attempts = static_cast<uint16_t>((state_->attempts << 1) | in.scanFailed);

  // Every rule compares one value with its thresholds; build the thirteen values, and the set of rules that
  // have one to look at now, then one loop does the rest. Value limits are only looked at with fresh data:
  // missing data neither trips nor clears them. The device rule's value is the paths the monitor's own
  // protection holds (or is about to hold) off: both at once on the fault line, which says nothing about
  // which flag rose, and what the flags say with each fresh scan (the scan after the line names it). The
  // freshness rules' values are 1 while the data is stale or the link is lost; the open-wire rule's is 1
  // while the last scan shows an open sense wire. A board that never answered counts as stale from start-up.
  const PackView* pack = in.pack;
  const PackTotals* t = &pack->totals;
  int32_t value[kFaultCount];  // each read only where `evaluated` has its bit, and those are all written
  // While the monitor's first bring-up runs within its bound (PackView::startupGrace) nothing is stale or
  // lost yet: a 64-device BQ79616 chain takes about 1 s to bring up, three times the default stale limit.
  const bool grace = pack->inStartupGrace(now);
  FaultMask evaluated = grace ? 0 : bit(FaultId::StaleData);
  if (in.fresh) {
    if (t->cells) {
      value[0] = t->extreme[kMaxCell];
      value[1] = t->extreme[kMinCell];
      evaluated |= bit(FaultId::CellOvervoltage) | bit(FaultId::CellUndervoltage);
      if (pack->hasCurrent) {
        value[2] = value[3] = pack->currentMa;
        evaluated |= bit(FaultId::ChargeOvercurrent) | bit(FaultId::DischargeOvercurrent);
      }
    }
    if (t->temps) {
      value[4] = value[10] = t->extreme[kMaxTemp];
      value[5] = value[11] = t->extreme[kMinTemp];
      evaluated |= bit(FaultId::OvertempDischarge) | bit(FaultId::UndertempDischarge) |
                   bit(FaultId::OvertempCharge) | bit(FaultId::UndertempCharge);
    }
    value[9] = t->openWire;
    evaluated |= bit(FaultId::OpenWire);
    state_->deviceBlocks = pack->deviceBlocks;
  }
  if (in.faultLine) state_->deviceBlocks = static_cast<uint8_t>(Action::AllOff);
  value[6] = state_->deviceBlocks;
  if (in.fresh || in.faultLine) evaluated |= bit(FaultId::DeviceSafety);
  // In pack storage the scans are further apart: stale after as many of them (PackView::storage).
  value[7] = elapsed(t->oldest, now).us > config_.staleAfter.us + pack->storage.staleExtra.us;
  value[8] = state_->failedScans >= config_.commLossScans;
  if ((in.fresh || in.scanFailed) && !grace)
    evaluated |= bit(FaultId::CommLoss) | bit(FaultId::CommErrorRate);
  // The failures among the last rateWindow attempts: over a window, not in a row, so how the failures of an
  // intermittent link fall on the scan grid (which shifts with its onset) does not decide whether it trips.
  value[12] = countBits(state_->attempts & ((1U << config_.rateWindow) - 1U));

  // Then each enabled rule with something to look at moves its debounce, and the paths to open are the union
  // of the actions (ChargeOff and DischargeOff are bits) of every active fault; the device rule's are
  // narrowed to the paths its flags concern.
  uint8_t actions = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const Rule& rule = config_.rules[i];
    if (rule.enabled && (evaluated & (1U << i)) != 0) track(i, value[i], now, out);
    if ((state_->active & (1U << i)) == 0) continue;
    uint8_t action = static_cast<uint8_t>(rule.action);
    if (i == static_cast<uint8_t>(FaultId::DeviceSafety)) action &= state_->deviceBlocks;
    actions |= action;
  }
  out.active = state_->active;
  out.off = actions;
  return out;
}

void Protection::track(uint8_t i, int32_t v, Instant now, ProtectionState& out) {
  constexpr FaultMask kLowerLimits = bit(FaultId::CellUndervoltage) | bit(FaultId::DischargeOvercurrent) |
                                     bit(FaultId::UndertempDischarge) | bit(FaultId::UndertempCharge);
  const Rule& rule = config_.rules[i];
  const FaultMask b = static_cast<FaultMask>(1U << i);
  // A lower limit is an upper limit of the complemented values (~x = -1 - x reverses the order and, unlike
  // negation, never overflows), so one pair of comparisons serves both kinds.
  const int32_t flip = (kLowerLimits & b) != 0 ? -1 : 0;
  const int32_t x = v ^ flip;
  const bool present = x >= (rule.trip ^ flip);
  const bool absent = x < (rule.clear ^ flip);
  // What clearLatched() asks of a latched fault: the value past the clear threshold; for a current limit,
  // whose clear threshold lies on the relieving side of zero, no more than its magnitude flowing the tripped
  // way: the over-current is gone, and the path it holds off carries none of the relieving current.
  // Compared like the rest in the complemented order: the clear threshold, or for a current limit its
  // magnitude m on the tripped side (m for an upper limit; -m for a lower one, whose complement is m - 1).
  constexpr FaultMask kCurrentLimits = bit(FaultId::ChargeOvercurrent) | bit(FaultId::DischargeOvercurrent);
  int32_t release = rule.clear ^ flip;
  if ((kCurrentLimits & b) != 0) release = (rule.clear < 0 ? -rule.clear : rule.clear) + flip;
  state_->goneNow = static_cast<FaultMask>(x < release ? state_->goneNow | b : state_->goneNow & ~b);
  if (state_->trips[i] != 0) forgive(i, now);

  // Count consecutive sightings of the condition (while not tripped) or of its absence (while tripped); a
  // sighting of the other kind restarts the count.
  const bool tripped = (state_->active & b) != 0;
  uint8_t& count = state_->count[i];
  if (tripped ? present : absent) {
    count = 0;
    return;
  }
  if (!(tripped ? absent : present)) return;
#if FW_PROTECTION_DELAYS
  if (count == 0) state_->since[i] = now;
#endif
  if (count < 0xFF) ++count;
  if (count < (tripped ? rule.recover : rule.debounce)) return;
#if FW_PROTECTION_DELAYS
  if (elapsed(state_->since[i], now) < rule.delay) return;
#endif

  count = 0;
  if ((state_->latched & b) != 0) return;  // stays until clearLatched()
  state_->active ^= b;
  (tripped ? out.newlyCleared : out.newlyTripped) |= b;
  if (tripped) return;
  state_->tripped[i] = now;
  if (rule.latchTrips == 0) return;
  // Count the trip; the decay towards forgiving one restarts with it (TI does not say whether it does: the
  // restart forgives later, the safe side; README "Open questions").
  uint8_t& trips = state_->trips[i];
  if (trips < 0xFF) ++trips;
  state_->tripsSince[i] = now;
  if (trips >= rule.latchTrips) state_->latched |= b;
}

// Called with every fresh value while trips are counted, so tripsSince stays within one decay of now (an
// Instant compares correctly only within half the clock's 71-minute wrap).
void Protection::forgive(uint8_t i, Instant now) {
  const Duration decay = s(config_.rules[i].tripDecayS);
  if (decay.us == 0) return;  // never forgiven
  uint8_t& trips = state_->trips[i];
  Instant& since = state_->tripsSince[i];
  while (trips != 0 && elapsed(since, now) >= decay) {
    --trips;
    since = since + decay;
  }
}

FaultMask Protection::clearLatched() {
  FaultMask cleared = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const FaultMask b = static_cast<FaultMask>(1U << i);
    if ((state_->latched & b) == 0 || (state_->goneNow & b) == 0) continue;
    state_->active = static_cast<FaultMask>(state_->active & ~b);
    state_->latched = static_cast<FaultMask>(state_->latched & ~b);
    state_->count[i] = 0;
    cleared |= b;
  }
  return cleared;
}

const char* faultName(FaultId id) {
  switch (id) {
    case FaultId::CellOvervoltage:
      return "cell_ov";
    case FaultId::CellUndervoltage:
      return "cell_uv";
    case FaultId::ChargeOvercurrent:
      return "occ";
    case FaultId::DischargeOvercurrent:
      return "ocd";
    case FaultId::OvertempDischarge:
      return "otd";
    case FaultId::UndertempDischarge:
      return "utd";
    case FaultId::DeviceSafety:
      return "device_safety";
    case FaultId::StaleData:
      return "stale_data";
    case FaultId::CommLoss:
      return "comm_loss";
    case FaultId::OpenWire:
      return "open_wire";
    case FaultId::OvertempCharge:
      return "otc";
    case FaultId::UndertempCharge:
      return "utc";
    case FaultId::CommErrorRate:
      return "comm_rate";
  }
  return "?";
}

}  // namespace fw::app
