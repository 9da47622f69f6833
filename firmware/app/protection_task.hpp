// ProtectionTask: runs the firmware limits (protection.hpp) whenever new data arrives, a scan fails, the
// monitor's fault line asserts, or its periodic check comes due, and acts on the result.
//
// Acting goes through an Actuator, because images differ: on BQ769x2/BQ7690x images it is a FET command on
// the monitor's bus (it completes later, and the owner reports completion with actuated()); on BQ79616 and
// BQ4050 images it is the fault output pin (done at once). Every fault that trips is logged with when it was
// detected and when the action took effect, so the detection-to-FET-off latency is measurable (bms-sim prints
// it as protection_events).
//
// Events (post them to this task): kNewData (a scan validated), kScanFailed, kFaultLine (ALERT/nFAULT edge),
// kClearLatched (a user request). The periodic check is internal. Thread mode only.
#pragma once

#include <cstdint>
#include <span>

#include "app/pack_view.hpp"
#include "app/protection.hpp"
#include "app/publish_status.hpp"
#include "hal/gpio.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

class Actuator {
 public:
  // Requests the paths to be enabled or not. Returns true if the request is in effect on return, false if it
  // completes later (then the owner calls ProtectionTask::actuated()).
  virtual bool request(bool chargeOn, bool dischargeOn) = 0;

 protected:
  ~Actuator() = default;
};

// The fault output of images without FETs: asserted (driven to `activeLevel`) while any path must be off.
class FaultPinActuator final : public Actuator {
 public:
  FaultPinActuator(hal::DigitalOut& pin, bool activeLevel) : pin_(pin), active_(activeLevel) {}
  bool request(bool chargeOn, bool dischargeOn) override {
    pin_.set((chargeOn && dischargeOn) ? !active_ : active_);
    return true;
  }

 private:
  hal::DigitalOut& pin_;
  bool active_;
};

struct ProtectionRecord {  // all-zero until written: the log needs no constructor
  FaultId fault;
  bool actionDone;  // `acted` holds when the FET-off / fault output took effect
  bool cleared;
  Instant detected;
  Instant acted;
};

class ProtectionTask final : public sched::Task {
 public:
  static constexpr sched::EventMask kNewData = 0x1;
  static constexpr sched::EventMask kScanFailed = 0x2;
  static constexpr sched::EventMask kFaultLine = 0x4;
  static constexpr sched::EventMask kClearLatched = 0x8;
  static constexpr size_t kLogSize = 16;

  ProtectionTask(sched::Scheduler& scheduler, sched::TaskId id, const ProtectionConfig& config,
                 const PackView& pack, PublishStatus& status, Actuator& actuator, Duration checkPeriod);

  // Registers the task (watched by the watchdog supervisor) and arms its periodic check. Requests the paths
  // on, as the startup state (no fault known yet).
  void start();
  void run(sched::EventMask events) override;
  // The owner of a deferred actuator reports that the last request took effect.
  void actuated(Instant at);

  sched::TaskId id() const { return id_; }
  const Protection& protection() const { return protection_; }
  std::span<const ProtectionRecord> log() const { return {log_, logCount_}; }
  uint32_t evaluations() const { return evaluations_; }

 private:
  static constexpr sched::EventMask kTick = 0x10;
  void apply(const ProtectionState& st, Instant now);

  sched::Scheduler& scheduler_;
  sched::TaskId id_;
  const PackView& pack_;
  PublishStatus& status_;
  Actuator& actuator_;
  Protection protection_;
  Duration checkPeriod_;
  sched::Timer timer_;
  bool chargeOn_ = false;
  bool dischargeOn_ = false;
  bool requested_ = false;  // a request has been made since start()
  bool pendingAction_ = false;
  ProtectionRecord log_[kLogSize]{};
  size_t logCount_ = 0;
  uint32_t evaluations_ = 0;
};

}  // namespace fw::app
