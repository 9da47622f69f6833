// FetMailbox: protection's actuator on the BQ769x2/BQ7690x images. request() leaves the wanted state of the
// two paths here and posts monitor_event::kCommand to the monitor task; the monitor reads it when it runs
// next (right after protection: a scan in progress gives way at its next read) and sends the FET command
// ahead of its next scan. When the device has taken it, the monitor posts ProtectionTask::kActuated from the
// run() that handles the completion. Protection outranks the monitor and tasks run to completion, so it is
// the next task to run: the instant it takes as the log's `acted` follows the command's end by the rest of
// that run() (starting the next scan) and one dispatch, never a whole scan, and is never before it.
// Neither task holds a reference to the other; both hold this object.
// Where the board wires the device's CFETOFF / DFETOFF inputs to MCU pins, request() also drives them (high =
// that path off) before it returns: the path is off without I2C, whatever the link does. The request still
// completes as above (the command keeps the device's own state in step; the pins are not confirmation:
// protection takes that from the FET read-back of the next scan).
//
// Contract: thread mode only (protection's run() writes, the monitor's run() reads; run-to-completion tasks
// on one core need no lock).
#pragma once

#include <cstdint>

#include "app/monitors/monitor_task.hpp"
#include "app/protection/protection_task.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "hal/gpio.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

class FetMailbox final : public Actuator {
 public:
  explicit FetMailbox(sched::Scheduler& scheduler, hal::DigitalOut* chargeOffPin = nullptr,
                      hal::DigitalOut* dischargeOffPin = nullptr)
      : scheduler_(scheduler), chargeOffPin_(chargeOffPin), dischargeOffPin_(dischargeOffPin) {}

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
    if (chargeOffPin_ != nullptr) chargeOffPin_->set(!chargeOn);
    if (dischargeOffPin_ != nullptr) dischargeOffPin_->set(!dischargeOn);
    scheduler_.post(kMonitorTask, monitor_event::kCommand);
    return false;  // the monitor posts kActuated when the device has taken it
  }

  drivers::bq769x2::FetCommand command{};  // the latest request (the monitor reads it on kCommand)

 private:
  sched::Scheduler& scheduler_;
  hal::DigitalOut* chargeOffPin_;
  hal::DigitalOut* dischargeOffPin_;
};

}  // namespace fw::app
