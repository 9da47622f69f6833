// FetMailbox: protection's actuator on the BQ769x2/BQ7690x images. request() leaves the wanted state of the
// two paths here and posts monitor_event::kCommand to the monitor task; the monitor reads it when it runs
// next (right after protection: a scan in progress gives way at its next read) and sends the FET command
// ahead of its next scan. When the device has taken it, the monitor writes completedAt (the instant the
// command's transaction ended, taken in the monitor task as it handles the completion) and posts
// ProtectionTask::kActuated: the protection log's `acted` is that instant, not when protection got to run.
// Neither task holds a reference to the other; both hold this object.
//
// Contract: thread mode only (protection's run() writes, the monitor's run() reads; run-to-completion tasks
// on one core need no lock).
#pragma once

#include <cstdint>

#include "app/config.hpp"
#include "app/monitors/monitor_task.hpp"
#include "app/protection/protection_task.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "hal/gpio.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

inline constexpr bool kFaultIndicator = FW_BQ769X_FAULT_INDICATOR != 0;

class FetMailbox final : public Actuator {
 public:
  // `faultIndicator`: driven high while protection holds a path off, low while both are on (the G3507
  // image's fault output, PB26); nullptr: none. The FETs stay the device's to switch: the pin only tells
  // the outside.
  FetMailbox(sched::Scheduler& scheduler, hal::DigitalOut* faultIndicator)
      : scheduler_(scheduler), faultIndicator_(faultIndicator) {}

  bool request(bool chargeOn, bool dischargeOn) override {
    using drivers::bq769x2::FetCommand;
    static_assert(static_cast<uint8_t>(FetCommand::AllOn) == 0 &&
                  static_cast<uint8_t>(FetCommand::AllOff) == 1 &&
                  static_cast<uint8_t>(FetCommand::DischargeOff) == 2 &&
                  static_cast<uint8_t>(FetCommand::ChargeOff) == 3);
    // Indexed by (charge off, discharge off): on/on AllOn, on/off DischargeOff, off/on ChargeOff, off/off
    // AllOff.
    constexpr FetCommand kCommand[4] = {FetCommand::AllOn, FetCommand::DischargeOff, FetCommand::ChargeOff,
                                        FetCommand::AllOff};
    command = kCommand[(chargeOn ? 0 : 2) | (dischargeOn ? 0 : 1)];
    if (kFaultIndicator && faultIndicator_ != nullptr) faultIndicator_->set(!(chargeOn && dischargeOn));
    scheduler_.post(kMonitorTask, monitor_event::kCommand);
    return false;  // the monitor posts kActuated when the device has taken it
  }

  drivers::bq769x2::FetCommand command{};  // the latest request (the monitor reads it on kCommand)

 private:
  sched::Scheduler& scheduler_;
  hal::DigitalOut* faultIndicator_;
};

}  // namespace fw::app
