#include "app/protection_task.hpp"

namespace fw::app {

ProtectionTask::ProtectionTask(sched::Scheduler& scheduler, sched::TaskId id, const ProtectionConfig& config,
                               const PackView& pack, PublishStatus& status, Actuator& actuator,
                               Duration checkPeriod)
    : scheduler_(scheduler),
      id_(id),
      pack_(pack),
      status_(status),
      actuator_(actuator),
      protection_(config),
      checkPeriod_(checkPeriod) {}

void ProtectionTask::start() {
  scheduler_.addTask(id_, *this, {}, true);
  scheduler_.startTimer(timer_, id_, kTick, checkPeriod_, checkPeriod_);
}

void ProtectionTask::run(sched::EventMask events) {
  const Instant now = scheduler_.clock().now();
  ProtectionInputs in;
  in.pack = &pack_;
  in.fresh = (events & kNewData) != 0;
  in.scanFailed = (events & kScanFailed) != 0 && !in.fresh;
  in.faultLine = (events & kFaultLine) != 0;
  if ((events & kClearLatched) != 0) status_.pendingCleared |= protection_.clearLatched();
  const ProtectionState st = protection_.evaluate(in, now);
  ++evaluations_;
  apply(st, now);
  scheduler_.checkIn(id_);
}

void ProtectionTask::apply(const ProtectionState& st, Instant now) {
  status_.active = st.active;
  status_.pendingTripped |= st.newlyTripped;
  status_.pendingCleared |= st.newlyCleared;
  status_.faultOutput = st.faultOutput();

  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const FaultMask b = static_cast<FaultMask>(1U << i);
    if ((st.newlyCleared & b) != 0) {
      for (size_t k = logCount_; k-- > 0;) {
        if (log_[k].fault == static_cast<FaultId>(i) && !log_[k].cleared) {
          log_[k].cleared = true;
          break;
        }
      }
    }
    if ((st.newlyTripped & b) != 0 && logCount_ < kLogSize) {
      log_[logCount_++] = ProtectionRecord{static_cast<FaultId>(i), false, false, now, {}};
    }
  }

  const bool chargeOn = !st.chargeOff;
  const bool dischargeOn = !st.dischargeOff;
  if (requested_ && chargeOn == chargeOn_ && dischargeOn == dischargeOn_ && st.newlyTripped == 0) return;
  requested_ = true;
  chargeOn_ = chargeOn;
  dischargeOn_ = dischargeOn;
  pendingAction_ = true;
  if (actuator_.request(chargeOn, dischargeOn)) actuated(now);
}

void ProtectionTask::actuated(Instant at) {
  if (!pendingAction_) return;
  pendingAction_ = false;
  status_.chargeOn = chargeOn_;
  status_.dischargeOn = dischargeOn_;
  for (size_t k = 0; k < logCount_; ++k) {
    if (!log_[k].actionDone) {
      log_[k].acted = at;
      log_[k].actionDone = true;
    }
  }
}

}  // namespace fw::app
