// The application of the BQ769x2-family images (lp-mspm0l1306-bq76952, lp-mspm0l1306-bq76907 and
// lp-mspm0g3507-bq76952): one monitor device on I2C, FET control through it, SLCAN or CAN out.
//
// Tasks (priority = TaskId, higher first; app/tasks.hpp):
//   3 protection   firmware limits on every new scan, on ALERT at once (the pin's interrupt posts to it), and
//                  every scan period; FETs through the FetMailbox (fet_mailbox.hpp), which the monitor reads
//   2 monitor      MonitorTask<Bq769xDevice> (monitor_task.hpp): probe, configuration (one CONFIG_UPDATE,
//                  only if the device differs), FET enable, the
//                  run-time set-up (SLEEP disabled as TI's examples do: in SLEEP the device measures only
//                  every few seconds; Alarm Enable from the table's Default Alarm Mask), a scan every scan
//                  period; FET commands from protection go ahead of the next scan
// A scan whose Battery Status says SLEEP is allowed again means the device reset since the set-up (a reset
// reloads SLEEP_EN from Power Config and loses the RAM configuration: settings, FET_EN, SLEEP_DISABLE): the
// monitor goes through the set-up again at once, and then sends protection's last FET request again (a reset
// device has forgotten it).
//   1 publisher    SLCAN lines (L1306) or CAN frames (G3507), and the command answers
//   0 command      commands from the same line or bus (app/command): clear latched faults, hold paths off,
//                  identify, read and write the limits, enter the bootloader
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

#include "app/command/commands.hpp"
#include "app/config.hpp"
#include "app/monitors/fet_mailbox.hpp"
#include "app/monitors/monitor_task.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/slcan_publisher.hpp"
#include "core/stats.hpp"
#include "core/zeroed.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/serial.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

inline constexpr bool kConfigUpdate = FW_BQ769X_CONFIG_UPDATE != 0;
inline constexpr bool kFaultIndicator = FW_BQ769X_FAULT_INDICATOR != 0;
static_assert(!kConfigUpdate || drivers::bq769x2::kConfigPaths,
              "the start-up CONFIG_UPDATE needs the link's configuration paths (FW_BQ769X_CONFIG_PATHS)");

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
  // The BQ769x2's CFETOFF / DFETOFF inputs where the board wires them to MCU pins (bsp/mspm0/README.md
  // "Connections"; the settings table configures them active-high, that FET only): driven high while
  // protection holds the charge / discharge path off, so a path opens without I2C, at once, also when the
  // link has failed. nullptr: not wired (the BQ7690x has no such pins).
  hal::DigitalOut* chargeOffPin = nullptr;
  hal::DigitalOut* dischargeOffPin = nullptr;
};

// Statistics (core/stats.hpp: all 0 in a build without them).
struct Bq769xStats {
  uint32_t scans = 0;
  uint32_t scanFailures = 0;
  uint32_t fetCommands = 0;    // FET commands completed
  uint32_t setupAttempts = 0;  // probe/configure/FET-enable sequences started
  uint8_t configWrites = 0;    // settings the last configuration actually wrote (0: the device matched)
};

// Fills `sample` and the pack-level fields of `view` from a validated measurement (bq769x_app.cpp).
void toSample(const drivers::bq769x2::Bq769x2Measurement& m, uint8_t cells, BoardSample& sample,
              PackView& view);
void toSample(const drivers::bq769x2::Bq7690xMeasurement& m, uint8_t cells, BoardSample& sample,
              PackView& view);
// The paths the device's own protection holds off or is about to (its safety alert, status and permanent-fail
// flags, bit by bit; bq769x_app.cpp): PackView::deviceBlocks.
uint8_t deviceBlocks(const drivers::bq769x2::Bq769x2Measurement& m);
uint8_t deviceBlocks(const drivers::bq769x2::Bq7690xMeasurement& m);
// Temperature sensors each family reports: BQ769x2 internal, TS1, TS3; BQ7690x internal.
constexpr uint8_t tempsOf(const drivers::bq769x2::Bq769x2Measurement*) {
  return 3;
}
constexpr uint8_t tempsOf(const drivers::bq769x2::Bq7690xMeasurement*) {
  return 1;
}

// The BQ769x2/BQ7690x part of the monitor task (monitor_task.hpp): set-up is probe, configuration, FET
// enable and the run-time set-up; FET commands from protection (FetMailbox) go ahead of the next scan and
// make a scan in progress give way; three failed scans in a row probe again; a scan that shows SLEEP allowed
// again sets up again at once. kPublisherScanDone: the event that tells the publisher a scan ended (0: its
// cycles do not follow scans).
template <class Driver, class Measurement, sched::EventMask kPublisherScanDone_>
class Bq769xDevice : public MonitorBase {
 public:
  template <class... DriverArgs>
  Bq769xDevice(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert,
               const Bq769xAppConfig& config, BoardSample& sample, PackView& view, FetMailbox& fet,
               DriverArgs&&... driverArgs)
      : scheduler_(scheduler),
        alert_(alert),
        config_(config),
        sample_(sample),
        view_(view),
        fet_(fet),
        driver_(bus, scheduler.clock(),
                drivers::DriverContext{scheduler, kMonitorTask, monitor_event::kBus, monitor_event::kTimer},
                static_cast<DriverArgs&&>(driverArgs)..., config.monitor) {}

  const Driver& driver() const { return driver_; }
  const Bq769xStats& stats() const { return records_->stats; }

 protected:
  static constexpr bool kCommands = true;
  static constexpr sched::EventMask kPublisherScanDone = kPublisherScanDone_;
  enum class Step : uint8_t { Probe, Configure, FetEnable, RuntimeSetup };

  Duration scanPeriod() const { return config_.scanPeriod; }
  // Probe, CONFIG_UPDATE, FET enable, run-time set-up and the first scan, from power-up: two scan periods
  // (measured with every setting written: 130.5 ms on the BQ76952, 41 settings; 90.3 ms on the BQ76907, 12;
  // tests/latency/startup_grace_test.cpp holds each image to it).
  Duration firstDataBound() const { return config_.scanPeriod * 2; }
  static constexpr sched::EventMask driverEvents() { return monitor_event::kBus | monitor_event::kTimer; }
  // ALERT goes to protection alone, which opens the FETs without waiting for a scan (the scan after the
  // command says which fault it was; the protection log holds the trip and when it was detected).
  static constexpr bool kFaultLineToo = false;
  void attachFaultLine() { alert_.enable(scheduler_.notifier(kProtectionTask, ProtectionTask::kFaultLine)); }
  void scanTick() { flags_->fetBackoff = false; }  // a failed FET command is tried again once per scan period

  // Protection asked for the paths (FetMailbox::request()): the command goes out as soon as the bus is free.
  // A scan in progress gives way at its next read, and a scan follows the command (it tells which fault it
  // was, and replaces one that gave way): ALERT to FET-off within 2 ms (README "Figures", the budget) needs
  // the command not to wait for a whole scan (~2 ms). The fault indicator follows the request as this task
  // takes it (it runs right after protection, before the command goes out).
  void commandPosted() {
    flags_->fetWanted = true;
    flags_->fetRequested = true;
    flags_->fet = fet_.command;
    if (kFaultIndicator && config_.faultIndicator != nullptr)
      config_.faultIndicator->set(flags_->fet != drivers::bq769x2::FetCommand::AllOn);
    if (loop_->op == MonitorOp::Scan) driver_.yieldScan();
    loop_->scanDue = true;
  }
  bool commandWaiting() const { return flags_->fetWanted && !flags_->fetBackoff; }
  Status startCommand() {
    flags_->fetWanted = false;
    return driver_.startFet(flags_->fet);
  }
  void commandFinished(Status result) {
    if (result == Status::Ok) {
      if (kStats) ++records_->stats.fetCommands;
      scheduler_.post(kProtectionTask, ProtectionTask::kActuated);  // protection runs next (fet_mailbox.hpp)
    } else {
      // The device did not take it (gone, resetting): keep scanning, and try again next period. The device's
      // own protection stays the backstop meanwhile.
      flags_->fetWanted = true;
      flags_->fetBackoff = true;
    }
  }

  Status startSetup() {
    if (flags_->step == Step::Probe) {
      if (kStats) ++records_->stats.setupAttempts;
      return driver_.startProbe(records_->identity);
    }
    if (flags_->step == Step::RuntimeSetup) return driver_.startRuntimeSetup(config_.settings);
    return kConfigUpdate && flags_->step == Step::Configure ? driver_.startConfigure(config_.settings)
                                                            : driver_.startFetEnable();
  }
  void setupFinished(Status result) {
    // A probe that failed found no device: probe again next scan period (two subcommand reads, harmless), so
    // a device that comes back is set up within one scan period plus one bring-up. A later step that failed
    // waits the retry interval.
    if (result != Status::Ok)
      return retryLater(flags_->step == Step::Probe ? config_.scanPeriod : config_.retryInterval);
    if (kStats && kConfigUpdate && flags_->step == Step::Configure)
      records_->stats.configWrites = driver_.written();
    if (flags_->step == Step::RuntimeSetup) {
      flags_->step = Step::Probe;  // where the next set-up starts
      setRunning(view_, true);
      loop_->scanDue = true;
      flags_->fetWanted =
          flags_->fetRequested;  // protection's last request, again: the device may have reset
      return;
    }
    // Without the start-up CONFIG_UPDATE the probe is followed by FET enable.
    flags_->step = static_cast<Step>(static_cast<uint8_t>(flags_->step) +
                                     (!kConfigUpdate && flags_->step == Step::Probe ? 2 : 1));
  }
  Status startScan() { return driver_.startScan(records_->measurement); }
  ScanVerdict scanFinished(Status result, Instant) {
    if (result == Status::Aborted)
      return {.measured = false};  // gave way to a FET command: not a measurement
    sample_.last = result;
    if (result == Status::Ok) {
      toSample(records_->measurement, config_.cells, sample_, view_);
      // The device reset since the set-up: set it up again now (the measurement itself is valid).
      if (records_->measurement.reg.batteryStatus.sleep_en()) {
        setRunning(view_, false);
        loop_->retryDue = true;
      }
    }
    return {.newData = result == Status::Ok, .failed = result != Status::Ok};
  }
  void afterSummarize() {}
  // The device stopped answering or keeps failing: go through probe and configuration again, starting with a
  // probe at the next scan period.
  void recover() { retryLater(config_.scanPeriod); }

  // Starts over from the probe after `wait` (the device may have reset or be absent; a reset loses its RAM
  // configuration).
  void retryLater(Duration wait) {
    setRunning(view_, false);
    flags_->step = Step::Probe;
    loop_->retryDue = false;
    scheduler_.startTimer(records_->retryTimer, kMonitorTask, monitor_event::kRetry, wait);
  }

  // What changes, zero at construction (one block each, no per-member start-up code): the small fields
  // first (Cortex-M0+ byte loads reach only 31 bytes past the object's address), the records after the
  // references, the driver with its buffers last.
  struct Flags {
    Step step;  // the next set-up step (Probe while running)
    bool fetWanted;
    bool fetRequested;  // protection has made a request (fet is its latest)
    bool fetBackoff;
    drivers::bq769x2::FetCommand fet;  // meaningful while fetWanted
  };
  struct Records {
    Bq769xStats stats;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    drivers::bq769x2::Identity identity;
    Measurement measurement;
  };
  Zeroed<Flags> flags_;
  sched::Scheduler& scheduler_;
  hal::EdgeInput& alert_;
  const Bq769xAppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  FetMailbox& fet_;
  Zeroed<Records> records_;
  Driver driver_;
};
template <class Driver, class Measurement, sched::EventMask kPublisherScanDone>
using Bq769xMonitor = MonitorTask<Bq769xDevice<Driver, Measurement, kPublisherScanDone>>;

// The publisher that suits the image's output: SLCAN text on a serial line, or CAN frames.
inline SlcanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::SerialTx& out,
                                    FramePlan& plan) {
  return SlcanPublisher(s, id, out, plan, ms(100), 10);
}
inline CanPublisher makePublisher(sched::Scheduler& s, sched::TaskId id, hal::CanBus& out, FramePlan& plan) {
  return CanPublisher(s, id, out, plan, CanLayout::Native, ms(100), 10);
}

// The composition: one board, the monitor, protection, its FET actuator (the mailbox both tasks hold), the
// publisher and the command task. `output` is a CanBus (G3507) or a SerialPort (L1306: SLCAN out and in).
template <class Driver, class Measurement, class Publisher>
class Bq769xApp {
 public:
  static constexpr sched::TaskId kProtectionId = kProtectionTask;
  static constexpr sched::TaskId kPublisherId = kPublisherTask;

  template <class Output, class... DriverArgs>
  Bq769xApp(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert, Output& output,
            hal::SystemControl& system, const Bq769xAppConfig& config, DriverArgs&&... driverArgs)
      : plan_(*view_, *addressOf(status_), kDefaultLimits.staleAfter),  // status_ is built after plan_
        fet_(scheduler, config.chargeOffPin, config.dischargeOffPin),
        settings_(kDefaultLimits),
        protection_(scheduler, kProtectionId, settings_.limits(), *view_, *status_, fet_, config.scanPeriod),
        publisher_(makePublisher(scheduler, kPublisherId, output, plan_)),
        command_({scheduler, protection_, settings_, system, command::kNode}, output, publisher_.outbox(),
                 system),
        monitor_(scheduler, bus, alert, config, *addressOf(sample_), *view_, fet_,
                 static_cast<DriverArgs&&>(driverArgs)...) {
    // The view's shape; the rest of it (and the publish status) starts zero, as Zeroed blocks do.
    view_->cellsPerBoard = config.cells;
    view_->tempsPerBoard = tempsOf(static_cast<Measurement*>(nullptr));
    view_->hasFetStatus = true;  // every scan reads the FETs' state back
    view_->boards = {&*sample_, 1};
  }

  [[gnu::always_inline]] void start() {  // one caller (the image's appInit): folded into it
    protection_.setLimitUpdate(settings_);
    protection_.start();
    monitor_.start();
    publisher_.start();
    command_.start();
  }

  const PackView& pack() const { return *view_; }
  const PublishStatus& status() const { return *status_; }
  // The Startup message (reset cause, version, surviving fault record), once, first in the next cycle.
  void announceStartup(const StartupInfo& info) { plan_.announceStartup(info); }
  const ProtectionTask& protection() const { return protection_; }
  const command::LimitSettings& settings() const { return settings_; }
  using Commands = command::CommandTask<command::LinkFor<Publisher>>;
  const Commands& commands() const { return command_; }
  using Monitor = Bq769xMonitor<Driver, Measurement, Publisher::kScanDone>;
  const Monitor& monitor() const { return monitor_; }
  const Publisher& publisher() const { return publisher_; }

 private:
  // Member order only decides where the constructor's stores land (Thumb stores reach 124 bytes past a
  // base register, farther ones cost an address computation each): the wiring first, the zero blocks last.
  Zeroed<PackView> view_;
  FramePlan plan_;
  Zeroed<PublishStatus> status_;
  FetMailbox fet_;
  command::LimitSettings settings_;
  ProtectionTask protection_;
  Publisher publisher_;
  Commands command_;
  Monitor monitor_;
  Zeroed<BoardSample> sample_;
};

}  // namespace fw::app
