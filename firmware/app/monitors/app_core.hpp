// AppCore<Actuator, Publisher>: what every image's application composes around its monitor, once. The
// applications (Bq769xApp, Bq79616App, Bq4050App) derive from it and add their monitor task, last (its
// driver's buffers would push everything after it out of Thumb's short load/store reach), and the pack view's
// shape.
//
//   view_        the pack as the monitor last measured it (PackView), zero at construction (Zeroed)
//   plan_        which frames go out when (FramePlan), reading the view and the status
//   status_      the publish status: active faults and flags (zero at construction)
//   actuator_    how protection opens the paths: the FET mailbox the BQ769x monitor takes commands from, or
//                the fault output pin (FaultPinActuator)
//   settings_    the limits, their defaults from the image's limit table and the command interface's writes
//   protection_  the firmware limits on every scan, on the fault line and every scan period
//   publisher_   SLCAN text on a serial line (L1306) or CAN frames (G3507)
//   command_     the command interface on the same line or bus
//
// start(): protection first (it owns the fault line), the monitor (the derived class's startMonitor()), then
// the publisher and the command task. Tasks by priority: app/tasks.hpp.
#pragma once

#include <type_traits>

#include "app/balancing/balancing_policy.hpp"
#include "app/command/commands.hpp"
#include "app/monitors/storage_mode.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/slcan_publisher.hpp"
#include "app/tasks.hpp"
#include "core/zeroed.hpp"
#include "hal/can_bus.hpp"
#include "hal/serial.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

// The publisher that suits the image's output: SLCAN text on a serial line (native layout only), or CAN
// frames in `layout`.
inline SlcanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::SerialTx& out,
                                    FramePlan& plan, CanLayout) {
  return SlcanPublisher(s, id, out, plan, kFastPeriod, kSlowEvery);
}
inline CanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::CanBus& out, FramePlan& plan,
                                  CanLayout layout) {
  return CanPublisher(s, id, out, plan, layout, kFastPeriod, kSlowEvery);
}

template <class Actuator, class Publisher>
class AppCore {
 public:
  static constexpr sched::TaskId kProtectionId = kProtectionTask;
  static constexpr sched::TaskId kPublisherId = kPublisherTask;
  using Commands = command::CommandTask<command::LinkFor<Publisher>>;

  const PackView& pack() const { return *view_; }
  const PublishStatus& status() const { return *status_; }
  const ProtectionTask& protection() const { return protection_; }
  const command::LimitSettings& settings() const { return settings_; }
  command::LimitSettings& settings() { return settings_; }  // the record store restores and keeps them
  const Publisher& publisher() const { return publisher_; }
  const Commands& commands() const { return command_; }
  // The Startup message (reset cause, version, surviving fault record), once, first in the next cycle.
  void announceStartup(const StartupInfo& info) { plan_.announceStartup(info); }
  // The record store's hooks (FW_RECORD_STORE, app/store/persistence.hpp): trips to `observer`, its flash
  // jobs in the command task. Before start().
  void attachStore(TripObserver& observer, BackgroundWork& work) {
    protection_.setTripObserver(observer);
    command_.setBackground(work);
  }

 protected:
  // `output` is the image's line or bus (a SerialPort or a CanBus: out for the publisher, in for the
  // commands); `actuatorArgs` build the actuator.
  template <class Output, class... ActuatorArgs>
  AppCore(sched::Scheduler& scheduler, const ProtectionConfig& limits, Duration scanPeriod, Output& output,
          hal::SystemControl& system, CanLayout layout, ActuatorArgs&&... actuatorArgs)
      : plan_(*view_, *addressOf(status_), limits.staleAfter),  // status_ is built after plan_
        actuator_(static_cast<ActuatorArgs&&>(actuatorArgs)...),
        settings_(limits),
        protection_(scheduler, kProtectionId, settings_.limits(), *view_, *status_, actuator_, scanPeriod),
        publisher_(makePublisher(scheduler, kPublisherId, output, plan_, layout)),
        command_({scheduler, protection_, settings_, system, command::kNode}, output, publisher_.outbox(),
                 system) {}

  // Protection, then the monitor, the publisher and the commands (`balancing`: the command interface's entry
  // to the monitor's balancing policy, nullptr where the image does not balance).
  template <class Monitor>
  void startAll(Monitor& monitor, BalancingPolicy* balancing, StorageState* storage = nullptr) {
    protection_.setLimitUpdate(settings_);
    protection_.start();
    monitor.start();
    publisher_.start();
    if (balancing != nullptr) command_.setBalancing(*balancing, *view_);
    if (storage != nullptr) command_.setStorage(*storage);
    command_.start();
  }

  // Member order only decides where the constructors' stores land (Thumb stores reach 124 bytes past a base
  // register, farther ones cost an address computation each): the plan between the two zero blocks was -48 B
  // on each BQ769x-family image against the three blocks first (measured before link-time optimisation and
  // still under it).
  Zeroed<PackView> view_;
  FramePlan plan_;
  Zeroed<PublishStatus> status_;
  Actuator actuator_;
  command::LimitSettings settings_;
  ProtectionTask protection_;
  Publisher publisher_;
  Commands command_;
};

}  // namespace fw::app
