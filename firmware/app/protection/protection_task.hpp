// ProtectionTask: runs the firmware limits (protection.hpp) whenever new data arrives, a scan fails, the
// fault line asserts, or its periodic check comes due, and acts on the result.
//
// Acting goes through an Actuator, because images differ: on BQ769x2/BQ7690x images it is a FET command on
// the monitor's bus (a mailbox the monitor task reads, monitors/fet_mailbox.hpp: it completes later, and the
// monitor posts kActuated as it handles the completion); on BQ79616 and BQ4050 images it is the fault
// output pin (done at once). Every fault that trips is logged with when it was detected, when the action
// took effect and when the paths were confirmed off, so the detection-to-FET-off latency is measurable
// (bms-sim prints it as protection_events). What the publishers say about the paths (PublishStatus::chargeOn,
// dischargeOn, pathsKnown) is only ever what was confirmed: on FET images the device's own FET read-back
// with each fresh scan (unknown from a failed scan or stale data until the next fresh one), on fault-output
// images the pin's state.
// Protection and the monitor hold no reference to each other: they share the PackView (the monitor writes,
// protection reads), the actuator, and events posted by task id.
//
// Events (post them to this task): kNewData (a scan validated), kScanFailed, kFaultLine (the ALERT/nFAULT
// edge, posted by the pin's interrupt itself), kActuated (a deferred request took effect: post it from the
// run() that saw it complete; this task, the highest priority, runs next, takes that instant and evaluates),
// kClearLatched (clearLatched() posts it). The periodic check is internal. The fault line counts as a fault
// only while PackView::monitorRunning says the monitor is set up: before, the edge only evaluates the limits
// as a periodic check would. Thread mode only.
//
// Latched faults clear only on a user action: clearLatched(), which the images' command task (app/command)
// calls on ClearFaults, so they build with FW_PROTECTION_CLEAR_LATCHED=1 (the default); with 0 it clears
// nothing and a latched fault stays until reset. kClearLatched (posted by clearLatched()) evaluates at once,
// so the paths follow. Host requests (app/command, PathRequest and bootloader entry): requestOff() holds
// paths off on top of whatever the faults ask (a request only ever opens a path), then post kHostRequest. A
// LimitUpdate, if set, is applied just before each evaluation of a new scan (kNewData), so the limits change
// only at a scan boundary.
#pragma once

#include <cstdint>
#include <span>

#include "app/config.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/protection.hpp"
#include "app/publish/publish_status.hpp"
#include "app/tasks.hpp"
#include "core/zeroed.hpp"
#include "hal/gpio.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

// A source of limit changes (app/command/settings.hpp), applied by the protection task just before it
// evaluates a new scan.
class LimitUpdate {
 public:
  virtual void apply() = 0;

 protected:
  ~LimitUpdate() = default;
};

// Told of every evaluation (app/store/persistence.hpp logs the trips in flash): the faults that tripped in
// it, and whether protection is settled (a scan ended and no path request is pending, so flash work now
// delays no FET command). Called from the protection task after it acted; must only note and post.
class TripObserver {
 public:
  virtual void evaluated(FaultMask newlyTripped, bool settled, Instant now) = 0;

 protected:
  ~TripObserver() = default;
};

class Actuator {
 public:
  // Requests the paths to be enabled or not. Returns true if the request is in effect on return, false if it
  // completes later: then its owner posts ProtectionTask::kActuated to the protection task when it does.
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
  bool actionDone;  // `acted` holds when the request took effect: the FET command completed, the pin driven
  bool cleared;
  // `confirmed` holds when the paths this fault opens (offPaths, Action bits) were seen off: on FET images
  // the first scan whose FET read-back (PackView::devicePaths) shows them off, on fault-output images the
  // instant the pin was driven (`acted`). Never set on what was only asked for.
  bool confirmedOff;
  uint8_t offPaths;
  Instant detected;
  Instant acted;
  Instant confirmed;
};

class ProtectionTask final : public sched::Task {
 public:
  static constexpr sched::EventMask kNewData = 0x1;
  static constexpr sched::EventMask kScanFailed = 0x2;
  static constexpr sched::EventMask kFaultLine = 0x4;
  static constexpr sched::EventMask kClearLatched = 0x8;
  static constexpr sched::EventMask kActuated = 0x20;
  static constexpr sched::EventMask kHostRequest = 0x40;
  // Trips logged since start-up (the log does not wrap: later trips are not logged once it is full). Images
  // may shorten it (FW_PROTECTION_LOG_SIZE), or leave it out with 0 (the L1306 images: nothing in them
  // reads it; log() is then empty); the host keeps 16 for bms-sim.
  static constexpr size_t kLogSize = FW_PROTECTION_LOG_SIZE;

  // Inline: an image constructs it once, and the constructor is then stores only.
  ProtectionTask(sched::Scheduler& scheduler, sched::TaskId id, const ProtectionConfig& config,
                 const PackView& pack, PublishStatus& status, Actuator& actuator, Duration checkPeriod)
      : id_(id),
        scheduler_(scheduler),
        pack_(pack),
        status_(status),
        actuator_(actuator),
        checkPeriod_(checkPeriod),
        protection_(config) {}

  // Registers the task (watched by the watchdog supervisor) and arms its periodic check. The first request
  // to the actuator waits for the first fresh measurement or the first fault (stale data at the latest):
  // until then the outputs stay as reset left them (a fault pin asserted, the monitor's FETs its own).
  void start() {
    scheduler_.addTask(id_, *this, {}, true);
    scheduler_.startTimer(state_->timer, id_, kTick, untilGrid(scheduler_.now(), checkPeriod_), checkPeriod_);
  }
  void run(sched::EventMask events) override;

  // The paths the host wants held off (Action bits: ChargeOff, DischargeOff), in effect from the next run
  // (post kHostRequest). They add to what the faults ask; nothing here can turn a path on.
  void requestOff(uint8_t actions) { state_->hostOff = actions; }
  // Clears the latched faults whose condition is gone now (Protection::clearLatched) and posts kClearLatched
  // so the paths follow at once. Returns false if a latched fault stays because its condition is still
  // there (true: every latched fault cleared, or none was latched). Thread mode (the command task).
  bool clearLatched();
  void setLimitUpdate(LimitUpdate& update) { update_ = &update; }
  // Images with the record store (FW_RECORD_STORE) only.
  void setTripObserver(TripObserver& observer) { state_->observer.set(observer); }
  // Both paths off, and the actuator has confirmed it (FETs commanded off / fault output asserted).
  bool pathsOffConfirmed() const {
    return state_->requested && !state_->pendingAction && state_->off == static_cast<uint8_t>(Action::AllOff);
  }

  sched::TaskId id() const { return id_; }
  const Protection& protection() const { return protection_; }
  std::span<const ProtectionRecord> log() const { return {state_->log, state_->logCount}; }
  uint32_t evaluations() const { return state_->evaluations; }

 private:
  static constexpr sched::EventMask kTick = 0x10;
  inline void apply(const ProtectionState& st, bool fresh, Instant now);
  inline void record(const ProtectionState& st, Instant now);  // the log's part of apply()
  void actuated(Instant at);                                   // the last request took effect at `at`
  // What the publishers report about the paths, from this evaluation's inputs (FET images only).
  inline void readBack(const ProtectionInputs& in, Instant now);
  void confirm(uint8_t offNow, Instant at);  // records whose paths are all in `offNow` are confirmed at `at`

  // Everything that changes, zero at construction (one block: no per-member start-up code). Byte fields
  // first: Cortex-M0+ byte loads reach only 31 bytes past the object's address.
  struct State {
    uint8_t off;     // the paths last requested off (Action bits); read only once `requested`
    bool requested;  // a request has been made since start()
    bool pendingAction;
    bool resultSinceTick;  // run() evaluated for something else than the periodic tick alone since the last
                           // tick
    uint8_t hostOff;       // Action bits the host holds off (requestOff)
    uint8_t logCount;
    uint32_t evaluations;
    sched::Timer timer;
    ProtectionRecord log[kLogSize != 0 ? kLogSize : 1];
    [[no_unique_address]] StoreHook<TripObserver> observer;  // zero until setTripObserver()
  };
  // The references every run() uses before the state: with the log inside, the state would push them past
  // the 124 bytes a Thumb load reaches from the object's address; its byte fields stay within 31 bytes.
  // Still pays under link-time optimisation: the state first is +28..+36 B per image (measured).
  sched::TaskId id_;
  sched::Scheduler& scheduler_;
  const PackView& pack_;
  PublishStatus& status_;
  Actuator& actuator_;
  LimitUpdate* update_ = nullptr;
  Zeroed<State> state_;
  Duration checkPeriod_;
  Protection protection_;
};

}  // namespace fw::app
