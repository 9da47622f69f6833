// The application of the BQ769x2-family images (lp-mspm0l1306-bq76952, lp-mspm0l1306-bq76907 and
// lp-mspm0g3507-bq76952): one monitor device on I2C, FET control through it, SLCAN or CAN out.
//
// Tasks (priority = TaskId, higher first):
//   2 protection   firmware limits on every new scan, on ALERT at once, and every scan period
//   1 monitor      probe, configuration (one CONFIG_UPDATE, only if the device differs), FET enable, the
//                  run-time set-up (SLEEP disabled as TI's examples do: in SLEEP the device measures only
//                  every few seconds; Alarm Enable from the table's Default Alarm Mask), a scan every scan
//                  period; FET commands from protection go ahead of the next scan
// A scan whose Battery Status says SLEEP is allowed again means the device reset since the set-up (a reset
// reloads SLEEP_EN from Power Config and loses the RAM configuration: settings, FET_EN, SLEEP_DISABLE): the
// monitor goes through the set-up again at once, and then sends protection's last FET request again (a reset
// device has forgotten it).
//   0 publisher    SLCAN lines (L1306) or CAN frames (G3507)
// ALERT is configured (the settings table: Default Alarm Mask, and on the BQ769x2 ALERT Pin Config:
// active-low, open drain) to assert on the device's safety alerts, safety status and permanent-fail flags
// only, so the line itself is a fault signal: its falling edge makes protection open the FETs without waiting
// for a scan, and the scan that follows says which fault it was and clears Alarm Status, so the next event is
// a new edge. Bq769xMonitor is a template over the driver class (Bq769x2 or Bq7690x) so each image carries
// one copy of exactly the code it uses.
//
// The start-up CONFIG_UPDATE is built unless FW_BQ769X_CONFIG_UPDATE is 0 (app/config.hpp; every image builds
// it). With 0 the monitor goes from the probe straight to FET enable and runs on the device's stored
// configuration: the settings table is neither compared nor written (Bq769xAppConfig::settings is ignored,
// stats().configWrites stays 0).
#pragma once

#include <cstdint>
#include <span>

#include "app/config.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/slcan_publisher.hpp"
#include "core/stats.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/serial.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

inline constexpr bool kConfigUpdate = FW_BQ769X_CONFIG_UPDATE != 0;
inline constexpr bool kFaultIndicator = FW_BQ769X_FAULT_INDICATOR != 0;
static_assert(!kConfigUpdate || drivers::bq769x2::kConfigPaths,
              "the start-up CONFIG_UPDATE needs the link's configuration paths (FW_BQ769X_CONFIG_PATHS)");

// The tasks of the application, by priority (TaskId).
inline constexpr sched::TaskId kBq769xPublisherTask = 0;
inline constexpr sched::TaskId kBq769xMonitorTask = 1;
inline constexpr sched::TaskId kBq769xProtectionTask = 2;

struct Bq769xAppConfig {
  std::span<const drivers::bq769x2::Setting> settings{};  // the CONFIG_UPDATE table applied at start-up
  uint8_t cells = 16;                                     // cells connected
  drivers::bq769x2::MonitorConfig monitor{};
  Duration scanPeriod = ms(100);
  // After a set-up step past the probe failed (the device answers but refuses its configuration): the wait
  // before the next attempt, so CONFIG_UPDATE (which stops the device's protections) is not entered over and
  // over. A device that does not answer is probed again every scan period instead.
  Duration retryInterval = s(1);
  // Driven high while protection holds a path off, low while both are on (the G3507 image's fault output,
  // PB26); nullptr: none. The FETs stay the device's to switch: this pin only tells the outside.
  hal::DigitalOut* faultIndicator = nullptr;
};

// Statistics (core/stats.hpp: all 0 in a build without them).
struct Bq769xStats {
  uint32_t scans = 0;
  uint32_t scanFailures = 0;
  uint32_t alerts = 0;         // ALERT edges while running
  uint32_t fetCommands = 0;    // FET commands completed
  uint32_t setupAttempts = 0;  // probe/configure/FET-enable sequences started
  uint8_t configWrites = 0;    // settings the last configuration actually wrote (0: the device matched)
};

// Fills `sample` and the pack-level fields of `view` from a validated measurement (bq769x_app.cpp).
void toSample(const drivers::bq769x2::Bq769x2Measurement& m, uint8_t cells, BoardSample& sample,
              PackView& view);
void toSample(const drivers::bq769x2::Bq7690xMeasurement& m, uint8_t cells, BoardSample& sample,
              PackView& view);
// Temperature sensors each family reports: BQ769x2 internal, TS1, TS3; BQ7690x internal.
constexpr uint8_t tempsOf(const drivers::bq769x2::Bq769x2Measurement*) {
  return 3;
}
constexpr uint8_t tempsOf(const drivers::bq769x2::Bq7690xMeasurement*) {
  return 1;
}

// kPublisherScanDone: the event that tells the publisher a scan ended (0: its cycles do not follow scans).
template <class Driver, class Measurement, sched::EventMask kPublisherScanDone>
class Bq769xMonitor final : public sched::Task, public Actuator {
 public:
  static constexpr sched::TaskId kId = kBq769xMonitorTask;

  template <class... DriverArgs>
  Bq769xMonitor(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert,
                const Bq769xAppConfig& config, BoardSample& sample, PackView& view,
                ProtectionTask& protection, DriverArgs&&... driverArgs)
      : scheduler_(scheduler),
        alert_(alert),
        config_(config),
        sample_(sample),
        view_(view),
        protection_(protection),
        driver_(bus, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer},
                static_cast<DriverArgs&&>(driverArgs)..., config.monitor) {}

  void start() {
    scheduler_.addTask(kId, *this, {}, true);
    alert_.enable(scheduler_.notifier(kId, kAlert));
    scheduler_.startTimer(records_.scanTimer, kId, kScanTick, config_.scanPeriod, config_.scanPeriod);
    scheduler_.post(kId, kRetry);
  }

  // Actuator: protection asks for the paths; the FET command goes out as soon as the bus is free.
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
    flags_.fetWanted = true;
    flags_.fetRequested = true;
    flags_.fet = kCommand[(chargeOn ? 0 : 2) | (dischargeOn ? 0 : 1)];
    // A scan in progress gives way at its next read, and a scan follows the command (it tells which fault
    // it was, and replaces one that gave way): ALERT to FET-off within 2 ms (ARCHITECTURE.md budgets)
    // needs the command not to wait for a whole scan (~2 ms).
    if (flags_.op == Op::Scan) driver_.yieldScan();
    flags_.scanDue = true;
    if (kFaultIndicator && config_.faultIndicator != nullptr)
      config_.faultIndicator->set(!(chargeOn && dischargeOn));
    scheduler_.post(kId, kKick);
    return false;
  }

  void run(sched::EventMask events) override {
    // The driver's events are the two this task gave it (kBus, kTimer: the constructor's DriverContext).
    if ((events & (kBus | kTimer)) != 0 && driver_.onEvent(events) == drivers::Progress::Done) finished();
    if ((events & kAlert) != 0 && flags_.phase == Phase::Running) {
      // Protection (higher priority) runs next and asks for the FETs; nothing is started for the alert
      // before it has, so the command goes first and the scan after it says which fault it was.
      if (kStats) ++records_.stats.alerts;
      scheduler_.post(kBq769xProtectionTask, ProtectionTask::kFaultLine);
    }
    if ((events & kScanTick) != 0) {
      flags_.scanDue = true;
      flags_.fetBackoff = false;  // a failed FET command is tried again once per scan period
      scheduler_.checkIn(kId);
    }
    if ((events & kRetry) != 0) flags_.retryDue = true;
    if (!driver_.busy()) startNext();
  }

  const Driver& driver() const { return driver_; }
  const Bq769xStats& stats() const { return records_.stats; }
  bool running() const { return flags_.phase == Phase::Running; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kAlert = 0x4, kScanTick = 0x8, kRetry = 0x10,
                                    kKick = 0x20;
  enum class Phase : uint8_t { Probe, Configure, FetEnable, RuntimeSetup, Running };
  enum class Op : uint8_t { None, Setup, Scan, Fet };

  void startNext() {
    Status s = Status::Busy;
    Op op = Op::Setup;
    if (flags_.phase != Phase::Running) {
      if (flags_.scanDue) {
        flags_.scanDue =
            false;  // not measuring yet: protection counts the period as failed (stale, comm loss)
        scheduler_.post(kBq769xProtectionTask, ProtectionTask::kScanFailed);
      }
      if (!flags_.retryDue) return;
      if (flags_.phase == Phase::Probe) {
        if (kStats) ++records_.stats.setupAttempts;
        s = driver_.startProbe(records_.identity);
      } else if (flags_.phase == Phase::RuntimeSetup) {
        s = driver_.startRuntimeSetup(config_.settings);
      } else {
        s = kConfigUpdate && flags_.phase == Phase::Configure ? driver_.startConfigure(config_.settings)
                                                              : driver_.startFetEnable();
      }
    } else if (flags_.fetWanted && !flags_.fetBackoff) {
      flags_.fetWanted = false;
      s = driver_.startFet(flags_.fet);
      op = Op::Fet;
    } else if (flags_.scanDue) {
      flags_.scanDue = false;
      s = driver_.startScan(records_.measurement);
      op = Op::Scan;
    }
    flags_.op = s == Status::Ok ? op : Op::None;
  }

  // Starts over from the probe after `wait` (the device may have reset or be absent; a reset loses its RAM
  // configuration).
  void retryLater(Duration wait) {
    flags_.phase = Phase::Probe;
    flags_.retryDue = false;
    scheduler_.startTimer(records_.retryTimer, kId, kRetry, wait);
  }

  void finished() {
    const Instant now = scheduler_.now();
    const Status result = driver_.result();
    const Op op = flags_.op;
    flags_.op = Op::None;
    if (op == Op::Setup) {
      // A probe that failed found no device: probe again next scan period (two subcommand reads, harmless),
      // so a device that comes back is set up within one scan period plus one bring-up. A later step that
      // failed waits the retry interval.
      if (result != Status::Ok)
        return retryLater(flags_.phase == Phase::Probe ? config_.scanPeriod : config_.retryInterval);
      if (kStats && kConfigUpdate && flags_.phase == Phase::Configure)
        records_.stats.configWrites = driver_.written();
      // Without the start-up CONFIG_UPDATE the probe is followed by FET enable.
      flags_.phase = static_cast<Phase>(static_cast<uint8_t>(flags_.phase) +
                                        (!kConfigUpdate && flags_.phase == Phase::Probe ? 2 : 1));
      if (flags_.phase == Phase::Running) {
        flags_.scanDue = true;
        flags_.fetWanted =
            flags_.fetRequested;  // protection's last request, again: the device may have reset
      }
      return;
    }
    if (op == Op::Fet) {
      if (result == Status::Ok) {
        if (kStats) ++records_.stats.fetCommands;
        protection_.actuated(now);
      } else {
        // The device did not take it (gone, resetting): keep scanning, and try again next period. The
        // device's own protection stays the backstop meanwhile.
        flags_.fetWanted = true;
        flags_.fetBackoff = true;
      }
      return;
    }
    if (op != Op::Scan) return;
    if (result == Status::Aborted) return;  // gave way to a FET command (request()): not a measurement
    if (kStats) ++records_.stats.scans;
    sample_.last = result;
    sched::EventMask toProtection = ProtectionTask::kScanFailed;
    if (result == Status::Ok) {
      toSample(records_.measurement, config_.cells, sample_, view_);
      toProtection = ProtectionTask::kNewData;
      flags_.failedInRow = 0;
      if (records_.measurement.reg.batteryStatus.sleep_en()) {
        // The device reset since the set-up: set it up again now (the measurement itself is valid).
        flags_.phase = Phase::Probe;
        flags_.retryDue = true;
      }
    } else {
      if (kStats) ++records_.stats.scanFailures;
      // The device stopped answering or keeps failing: go through probe and configuration again, starting
      // with a probe at the next scan period.
      if (++flags_.failedInRow >= 3) {
        flags_.failedInRow = 0;
        retryLater(config_.scanPeriod);
      }
    }
    summarize(view_, now);
    scheduler_.post(kBq769xProtectionTask, toProtection);
    if constexpr (kPublisherScanDone != 0) scheduler_.post(kBq769xPublisherTask, kPublisherScanDone);
  }

  // What changes, zero at construction (one block each, no per-member start-up code): the small fields
  // first (Cortex-M0+ byte loads reach only 31 bytes past the object's address), the records after the
  // references, the driver with its buffers last.
  struct Flags {
    Phase phase;
    Op op;
    bool scanDue;
    bool retryDue;
    bool fetWanted;
    bool fetRequested;  // protection has made a request (flags_.fet is its latest)
    bool fetBackoff;
    drivers::bq769x2::FetCommand fet;  // meaningful while fetWanted
    uint8_t failedInRow;
  };
  struct Records {
    Bq769xStats stats;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    drivers::bq769x2::Identity identity;
    Measurement measurement;
  };
  Flags flags_{};
  sched::Scheduler& scheduler_;
  hal::EdgeInput& alert_;
  const Bq769xAppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  ProtectionTask& protection_;
  Records records_{};
  Driver driver_;
};

// The publisher that suits the image's output: SLCAN text on a serial line, or CAN frames.
inline SlcanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::SerialTx& out,
                                    FramePlan& plan) {
  return SlcanPublisher(s, id, out, plan, ms(100), 10);
}
inline CanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::CanBus& out, FramePlan& plan) {
  return CanPublisher(s, id, out, plan, CanLayout::Native, ms(100), 10);
}

// The composition: one board, the monitor (also protection's FET actuator), protection and the publisher.
template <class Driver, class Measurement, class Publisher>
class Bq769xApp {
 public:
  static constexpr sched::TaskId kProtectionId = kBq769xProtectionTask;
  static constexpr sched::TaskId kPublisherId = kBq769xPublisherTask;

  template <class Output, class... DriverArgs>
  Bq769xApp(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert, Output& output,
            const Bq769xAppConfig& config, DriverArgs&&... driverArgs)
      : view_{.cellsPerBoard = config.cells,
              .tempsPerBoard = tempsOf(static_cast<Measurement*>(nullptr)),
              .boards = {&sample_, 1}},
        plan_(view_, status_, kDefaultLimits.staleAfter),
        protection_(scheduler, kProtectionId, kDefaultLimits, view_, status_, monitor_, config.scanPeriod),
        publisher_(makePublisher(scheduler, kPublisherId, output, plan_)),
        monitor_(scheduler, bus, alert, config, sample_, view_, protection_,
                 static_cast<DriverArgs&&>(driverArgs)...) {}

  void start() {
    protection_.start();
    monitor_.start();
    publisher_.start();
  }

  const PackView& pack() const { return view_; }
  const PublishStatus& status() const { return status_; }
  const ProtectionTask& protection() const { return protection_; }
  using Monitor = Bq769xMonitor<Driver, Measurement, Publisher::kScanDone>;
  const Monitor& monitor() const { return monitor_; }
  const Publisher& publisher() const { return publisher_; }

 private:
  // Member order only decides where the constructor's stores land (Thumb stores reach 124 bytes past a
  // base register, farther ones cost an address computation each): the wiring first, the zero blocks last.
  PackView view_;
  FramePlan plan_;
  PublishStatus status_;
  ProtectionTask protection_;
  Publisher publisher_;
  Monitor monitor_;
  BoardSample sample_{};
};

}  // namespace fw::app
