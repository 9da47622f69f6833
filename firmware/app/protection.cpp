#include "app/protection.hpp"

namespace fw::app {
namespace {

struct Extremes {
  int32_t maxCell = INT32_MIN, minCell = INT32_MAX;
  int32_t maxTemp = INT32_MIN, minTemp = INT32_MAX;
  bool cells = false, temps = false, current = false;
};

// Extremes over the boards whose data is Valid now; the oldest board's age for the staleness rule.
Extremes extremes(const PackView& pack, Instant now, Duration staleAfter, uint32_t& oldestUs) {
  Extremes e;
  oldestUs = 0;
  for (size_t b = 0; b < pack.boards.size(); ++b) {
    const BoardSample& s = pack.boards[b];
    const uint32_t age = s.valid ? elapsed(s.takenAt, now).us : now.us;  // never valid: since start-up
    if (age > oldestUs) oldestUs = age;
    if (boardStatus(s, now, staleAfter) != BoardStatus::Valid) continue;
    for (uint8_t c = 0; c < pack.cellsPerBoard; ++c) {
      const int16_t v = s.cellMv[c];
      if (v > e.maxCell) e.maxCell = v;
      if (v < e.minCell) e.minCell = v;
      e.cells = true;
    }
    for (uint8_t t = 0; t < pack.tempsPerBoard; ++t) {
      const int16_t v = s.tempDeciK[t];
      if (v > e.maxTemp) e.maxTemp = v;
      if (v < e.minTemp) e.minTemp = v;
      e.temps = true;
    }
    if (b == 0) e.current = pack.hasCurrent;
  }
  return e;
}

constexpr bool isUpperLimit(FaultId id) {
  return id == FaultId::CellOvervoltage || id == FaultId::ChargeOvercurrent || id == FaultId::Overtemperature;
}

}  // namespace

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

  uint32_t oldestUs = now.us;  // no pack yet: everything is as old as the firmware
  Extremes e;
  if (in.pack != nullptr) e = extremes(*in.pack, now, config_.staleAfter, oldestUs);

  if (in.fresh && in.pack != nullptr) {
    for (uint8_t i = 0; i < kFaultCount; ++i) {
      const auto id = static_cast<FaultId>(i);
      const Rule& rule = config_.rules[i];
      if (!rule.enabled) continue;
      bool known = true;
      int32_t value = 0;
      switch (id) {
        case FaultId::CellOvervoltage:
          value = e.maxCell, known = e.cells;
          break;
        case FaultId::CellUndervoltage:
          value = e.minCell, known = e.cells;
          break;
        case FaultId::ChargeOvercurrent:
          value = in.pack->currentMa, known = e.current;
          break;
        case FaultId::DischargeOvercurrent:
          value = in.pack->currentMa, known = e.current;
          break;
        case FaultId::Overtemperature:
          value = e.maxTemp, known = e.temps;
          break;
        case FaultId::Undertemperature:
          value = e.minTemp, known = e.temps;
          break;
        default:
          continue;  // device and freshness rules are evaluated below
      }
      if (!known) continue;
      const bool upper = isUpperLimit(id);
      const bool present = upper ? value >= rule.trip : value <= rule.trip;
      const bool absent = upper ? value < rule.clear : value > rule.clear;
      update(id, present, absent, now, out);
    }
  }

  // The monitor's own protection: its fault line acts at once; its status registers with each fresh scan.
  const Rule& device = config_.rules[static_cast<uint8_t>(FaultId::DeviceSafety)];
  if (device.enabled && (in.fresh || in.faultLine)) {
    const bool fault = in.faultLine || (in.pack != nullptr && in.pack->deviceFault);
    update(FaultId::DeviceSafety, fault, !fault, now, out);
  }

  // Freshness: stale when the oldest board's newest valid sample is older than the limit (a board that never
  // answered counts from start-up); comm loss after consecutive failed scans.
  const Rule& stale = config_.rules[static_cast<uint8_t>(FaultId::StaleData)];
  if (stale.enabled) {
    const bool isStale = oldestUs > config_.staleAfter.us;
    update(FaultId::StaleData, isStale, !isStale, now, out);
  }
  const Rule& comm = config_.rules[static_cast<uint8_t>(FaultId::CommLoss)];
  if (comm.enabled && (in.fresh || in.scanFailed)) {
    const bool lost = failedScans_ >= config_.commLossScans;
    update(FaultId::CommLoss, lost, !lost, now, out);
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
