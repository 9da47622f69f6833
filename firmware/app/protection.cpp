#include "app/protection.hpp"

namespace fw::app {
// The six value limits come first in FaultId order, alternating upper and lower limits, so one loop handles
// them all.
static_assert(static_cast<uint8_t>(FaultId::CellOvervoltage) == 0 &&
              static_cast<uint8_t>(FaultId::CellUndervoltage) == 1 &&
              static_cast<uint8_t>(FaultId::ChargeOvercurrent) == 2 &&
              static_cast<uint8_t>(FaultId::DischargeOvercurrent) == 3 &&
              static_cast<uint8_t>(FaultId::Overtemperature) == 4 &&
              static_cast<uint8_t>(FaultId::Undertemperature) == 5);

void Protection::update(FaultId id, bool present, bool absent, Instant now, ProtectionState& out) {
  const uint8_t i = static_cast<uint8_t>(id);
  const Rule& rule = config_.rules[i];
  const FaultMask b = bit(id);
  Track& t = track_[i];
  if (present) conditionNow_ |= b;
  if (absent) conditionNow_ = static_cast<FaultMask>(conditionNow_ & ~b);

  // Count consecutive sightings of the condition (while not tripped) or of its absence (while tripped); a
  // sighting of the other kind restarts the count. Neither (no fresh data) leaves the count as it is.
  const bool tripped = (active_ & b) != 0;
  const bool towards = tripped ? absent : present;
  const bool away = tripped ? present : absent;
  if (away) {
    t.count = 0;
    return;
  }
  if (!towards) return;
  if (t.count == 0) t.since = now;
  if (t.count < 0xFF) ++t.count;
  if (t.count < rule.debounce || elapsed(t.since, now) < rule.delay) return;

  t.count = 0;
  if (!tripped) {
    active_ |= b;
    tripped_[i] = now;
    out.newlyTripped |= b;
  } else if (!rule.latch) {
    active_ = static_cast<FaultMask>(active_ & ~b);
    out.newlyCleared |= b;
  }
}

ProtectionState Protection::evaluate(const ProtectionInputs& in, Instant now) {
  ProtectionState out;

  if (in.fresh) {
    failedScans_ = 0;
  } else if (in.scanFailed && failedScans_ < 0xFF) {
    ++failedScans_;
  }

  // Every rule compares one value with its thresholds; build the nine values, then one loop does the rest.
  // The device rule's value is 1 while the monitor reports a fault (its line at once, its status with each
  // fresh scan); the freshness rules' values are 1 while the data is stale or the link is lost. A board
  // that never answered counts as stale from start-up.
  const PackTotals* t = in.pack != nullptr ? &in.pack->totals : nullptr;
  const bool fresh = in.fresh && t != nullptr;
  const bool current = fresh && in.pack->hasCurrent && t->cells;
  const int32_t amps = current ? in.pack->currentMa : 0;
  const bool fault = in.faultLine || (fresh && in.pack->deviceFault);
  const uint32_t age = t != nullptr ? elapsed(t->oldest, now).us : now.us;
  const int32_t value[kFaultCount] = {fresh ? t->maxCell : 0,
                                      fresh ? t->minCell : 0,
                                      amps,
                                      amps,
                                      fresh ? t->maxTemp : 0,
                                      fresh ? t->minTemp : 0,
                                      fault,
                                      age > config_.staleAfter.us,
                                      failedScans_ >= config_.commLossScans};
  const bool evaluated[kFaultCount] = {fresh && t->cells,
                                       fresh && t->cells,
                                       current,
                                       current,
                                       fresh && t->temps,
                                       fresh && t->temps,
                                       in.fresh || in.faultLine,
                                       true,
                                       in.fresh || in.scanFailed};
  constexpr FaultMask kLowerLimits =
      bit(FaultId::CellUndervoltage) | bit(FaultId::DischargeOvercurrent) | bit(FaultId::Undertemperature);
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const Rule& rule = config_.rules[i];
    if (!rule.enabled || !evaluated[i]) continue;
    const int32_t v = value[i];
    const bool lower = ((kLowerLimits >> i) & 1U) != 0;
    update(static_cast<FaultId>(i), lower ? v <= rule.trip : v >= rule.trip,
           lower ? v > rule.clear : v < rule.clear, now, out);
  }

  out.active = active_;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    if ((active_ & (1U << i)) == 0) continue;
    const auto action = static_cast<uint8_t>(config_.rules[i].action);
    out.chargeOff = out.chargeOff || (action & static_cast<uint8_t>(Action::ChargeOff)) != 0;
    out.dischargeOff = out.dischargeOff || (action & static_cast<uint8_t>(Action::DischargeOff)) != 0;
  }
  return out;
}

FaultMask Protection::clearLatched() {
  FaultMask cleared = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const FaultMask b = static_cast<FaultMask>(1U << i);
    if ((active_ & b) == 0 || !config_.rules[i].latch || (conditionNow_ & b) != 0) continue;
    active_ = static_cast<FaultMask>(active_ & ~b);
    track_[i] = Track{};
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
    case FaultId::Overtemperature:
      return "ot";
    case FaultId::Undertemperature:
      return "ut";
    case FaultId::DeviceSafety:
      return "device_safety";
    case FaultId::StaleData:
      return "stale_data";
    case FaultId::CommLoss:
      return "comm_loss";
  }
  return "?";
}

}  // namespace fw::app
