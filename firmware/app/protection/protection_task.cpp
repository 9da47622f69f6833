#include "app/protection/protection_task.hpp"

#include "core/stats.hpp"

namespace fw::app {

void ProtectionTask::run(sched::EventMask events) {
  // The periodic check is for when no scan result comes (a monitor stuck or not yet measuring): only the
  // stale-data rule can change without one. While results come every period it would evaluate the same data
  // a second time, so a tick alone is skipped when a result came since the last tick. That delays nothing:
  // staleness begins staleAfter after the last fresh result (1 s in the default limits, ten check periods),
  // and once results stop every tick from the second on evaluates again.
  const bool tick = events == kTick;
  const bool skip = tick && state_->resultSinceTick;
  state_->resultSinceTick = !tick;
  if (!skip) {
    const Instant now = scheduler_.now();
    ProtectionInputs in{};
    in.pack = &pack_;
    in.fresh = (events & kNewData) != 0;
    in.scanFailed = (events & kScanFailed) != 0;
    if (in.fresh && update_ != nullptr) update_->apply();  // limit changes: at a scan boundary, all at once
    // The fault line is a fault signal only while the monitor runs (PackView::monitorRunning): during
    // bring-up and recovery it is expected to be asserted.
    in.faultLine = ((events & kFaultLine) != 0) & pack_.monitorRunning;  // no branch: a byte load and an and
    const ProtectionState st = protection_.evaluate(in, now);
    if (kStats) ++state_->evaluations;
    // A deferred FET command completed. Its owner posts kActuated from the run() that handled the completion,
    // and this task outranks every other: it runs next, so now is when the command took effect (to within
    // the rest of that run()). Recorded before apply(), which may log new trips and ask for the next one.
    if ((events & kActuated) != 0) actuated(now);
    apply(st, in.fresh, now);
    // Settled: a scan ended and no path request is pending (taken once, before the read-back, which changes
    // neither: one call of the observer below, not one per way through readBack()).
    const bool settled = (events & (kNewData | kScanFailed)) != 0 && !state_->pendingAction;
    if (pack_.hasFetStatus) readBack(in, now);
    if constexpr (FW_RECORD_STORE != 0) {
      if (state_->observer.to != nullptr) state_->observer.to->evaluated(st.newlyTripped, settled, now);
    }
  }
  scheduler_.checkIn(id_);
}

bool ProtectionTask::clearLatched() {
  if (FW_PROTECTION_CLEAR_LATCHED) {
    status_.pendingCleared |= protection_.clearLatched();
    scheduler_.post(id_, kClearLatched);
  }
  return protection_.latched() == 0;
}

inline void ProtectionTask::apply(const ProtectionState& st, bool fresh, Instant now) {
  status_.active = st.active;
  if (kCoreMessages) {  // what ProtectionEvent reports
    status_.pendingTripped |= st.newlyTripped;
    status_.pendingCleared |= st.newlyCleared;
  }
  status_.faultOutput = st.faultOutput();
  if constexpr (kLogSize != 0) record(st, now);

  // The paths are Action bits from the faults to the actuator: what the faults open and what the host holds
  // off, one mask compared and kept (not a pair of flags each way).
  const uint8_t hostOff = state_->hostOff;
  const auto off = static_cast<uint8_t>((st.off | hostOff) & static_cast<uint8_t>(Action::AllOff));
  if (!state_->requested && !fresh && st.active == 0 && hostOff == 0)
    return;  // nothing measured, nothing wrong and nothing asked yet
  if (state_->requested && off == state_->off && st.newlyTripped == 0) return;
  state_->requested = true;
  state_->off = off;
  state_->pendingAction = true;
  if (actuator_.request((off & static_cast<uint8_t>(Action::ChargeOff)) == 0,
                        (off & static_cast<uint8_t>(Action::DischargeOff)) == 0))
    actuated(now);
}

// FET images: the paths as the device reports them with each fresh scan; unknown from a failed scan or stale
// data until the next fresh one. A record whose paths the scan shows off is confirmed (its `confirmed` is the
// evaluation of that scan, right after it ended).
inline void ProtectionTask::readBack(const ProtectionInputs& in, Instant now) {
  if (in.fresh) {
    const uint8_t on = pack_.devicePaths;
    status_.chargeOn = (on & static_cast<uint8_t>(Action::ChargeOff)) != 0;
    status_.dischargeOn = (on & static_cast<uint8_t>(Action::DischargeOff)) != 0;
    status_.pathsKnown = true;
    if constexpr (kLogSize != 0) confirm(static_cast<uint8_t>(~on & 3U), now);
  } else if (in.scanFailed || (status_.active & bit(FaultId::StaleData)) != 0) {
    status_.pathsKnown = false;
  }
}

void ProtectionTask::confirm(uint8_t offNow, Instant at) {
  for (uint8_t k = 0; k < state_->logCount; ++k) {
    ProtectionRecord& r = state_->log[k];
    if (r.confirmedOff || !r.actionDone || (r.offPaths & ~offNow) != 0) continue;
    r.confirmedOff = true;
    r.confirmed = at;
  }
}

// A fault that cleared closes its newest open record; one that tripped opens a record.
inline void ProtectionTask::record(const ProtectionState& st, Instant now) {
  FaultMask cleared = st.newlyCleared;
  for (uint8_t k = state_->logCount; k-- > 0 && cleared != 0;) {
    const FaultMask b = bit(state_->log[k].fault);
    if ((cleared & b) != 0 && !state_->log[k].cleared) {
      state_->log[k].cleared = true;
      cleared = static_cast<FaultMask>(cleared & ~b);
    }
  }
  // The log never wraps, so a new record's other fields are still zero (actionDone, cleared, acted).
  for (uint8_t i = 0; i < kFaultCount && state_->logCount < kLogSize; ++i) {
    if ((st.newlyTripped & (1U << i)) == 0) continue;
    ProtectionRecord& r = state_->log[state_->logCount++];
    r.fault = static_cast<FaultId>(i);
    r.detected = now;
    // The paths this fault opens (the device rule: those its flags concern now).
    r.offPaths = static_cast<uint8_t>(protection_.config().rules[i].action);
    if (i == static_cast<uint8_t>(FaultId::DeviceSafety)) r.offPaths &= protection_.deviceBlocks();
  }
}

void ProtectionTask::actuated(Instant at) {
  if (!state_->pendingAction) return;
  state_->pendingAction = false;
  // A pin is what it was driven to: confirmed now, and one signal for both paths (released only while both
  // may be on). FET images wait for the device's read-back (readBack()).
  const bool pin = !pack_.hasFetStatus;
  const bool released = state_->off == 0;
  if (pin) {
    status_.chargeOn = status_.dischargeOn = released;
    status_.pathsKnown = true;
  }
  if constexpr (kLogSize == 0) return;
  for (uint8_t k = 0; k < state_->logCount; ++k) {
    if (!state_->log[k].actionDone) {
      state_->log[k].acted = at;
      state_->log[k].actionDone = true;
    }
  }
  if (pin) confirm(state_->off, at);
}

}  // namespace fw::app
