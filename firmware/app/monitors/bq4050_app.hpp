// The application of the lp-mspm0g3507-bq4050 image: a BQ4050 gas gauge on SMBus, CAN out.
//
// Tasks (priority = TaskId, higher first; app/tasks.hpp):
//   3 protection   firmware limits on every new scan and every scan period; fault output pin (PB26)
//   2 monitor      MonitorTask<Bq4050Device> (monitor_task.hpp): probe (device type, PEC detection), then a
//                  scan every scan period; after three failed scans in a row it probes again at once (the
//                  gauge may have reset: PEC and device type are checked anew), and while probes fail, again
//                  every retry interval
//   1 publisher    CAN frames (native layout; the gauge's relative state of charge goes in PackSummary) and
//                  the command answers
//   0 command      commands from CAN (app/command)
// The gauge protects the pack with its own FETs (SafetyStatus); the firmware layer adds its limits and acts
// through the fault output, as on the BQ79616 image.
#pragma once

#include <cstdint>

#include "app/command/commands.hpp"
#include "app/monitors/app_core.hpp"
#include "app/monitors/monitor_task.hpp"
#include "app/monitors/storage_mode.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "core/zeroed.hpp"
#include "drivers/bq4050/gauge.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq4050AppConfig {
  drivers::bq4050::GaugeConfig gauge{};
  Duration scanPeriod = kScanPeriod;  // the default limits' debounce counts assume it (default_limits.hpp)
  Duration retryInterval = ms(100);   // between failed probes (a probe of an absent gauge is a few NACKs)
  // Pack storage (FW_STORAGE, storage_mode.hpp): the pack file's `storage`, the scan period only (the
  // gauge's own SLEEP is its business); scanEvery 0: none. Nothing in a build without it.
  [[no_unique_address]] StorageSettings storage{};
};

// The paths the gauge's own protection holds off (SafetyStatus, SLUUAQ3A chapter 2 "Protections": each
// protection's table names the FET it turns off, OperationStatus()[XCHG] or [XDSG]): charge for COV, OCC1/2,
// ASCC/ASCCL, OTC, UTC, PTO, CTO, OC, CHGC, CHGV, PCHGC; discharge for CUV, CUVC, OCD1/2, AOLD/AOLDL,
// ASCD/ASCDL, OTD, UTD; both for OTF and a permanent failure (PFStatus). Bit for bit, so a gauge that stops
// charging does not read as a pack that cannot discharge (bq4050_app.cpp).
uint8_t blockedPaths(const drivers::bq4050::Measurement& m);

struct Bq4050Stats : ScanStats {
  uint32_t probes = 0;
};

// The BQ4050's part of the monitor task (monitor_task.hpp): set-up is the probe; after three failed scans in
// a row it probes again at once (the gauge may have reset: PEC and device type are checked anew), and while
// probes fail, again every retry interval. A refused cell word (Implausible: an open sense line) is reported
// as open_wire and does not count toward the re-probe.
class Bq4050Device : public MonitorBase {
 public:
  // Inline: an image constructs it once, and the constructor is then stores only.
  Bq4050Device(sched::Scheduler& scheduler, hal::I2cBus& bus, const Bq4050AppConfig& config,
               BoardSample& sample, PackView& view, const PublishStatus& status)
      : scheduler_(scheduler),
        config_(config),
        sample_(sample),
        view_(view),
        storage_(config.storage, view, status),
        driver_(bus, scheduler.clock(),
                drivers::DriverContext{scheduler, kMonitorTask, monitor_event::kBus, monitor_event::kTimer},
                config.gauge) {}

  const drivers::bq4050::Gauge& gauge() const { return driver_; }
  const Bq4050Stats& stats() const { return records_->stats; }
  const drivers::bq4050::DeviceInfo& info() const { return records_->info; }
  // Pack storage: the command interface's entry (StorageMode::request).
  StorageState& storage() { return storage_; }

 protected:
  static constexpr bool kCommands = false;
  static constexpr sched::EventMask kPublisherScanDone = CanPublisher::kScanDone;

  Duration scanPeriod() const { return config_.scanPeriod; }
  // The probe and the first scan, from power-up (about 20 ms: the probe's few words and a 12.2 ms scan at
  // 100 kHz): one scan period.
  Duration firstDataBound() const { return config_.scanPeriod; }
  // The events this task gave the gauge (its DriverContext): driver_.events(), as constants.
  static constexpr sched::EventMask driverEvents() { return monitor_event::kBus | monitor_event::kTimer; }
  static constexpr bool kFaultLineToo = false;

  Status startSetup() {
    const Status s = driver_.startProbe(records_->info);
    if (s == Status::Ok) {
      loop_->retryDue = false;
      ++records_->stats.probes;
    }
    return s;
  }
  void setupFinished(Status result) {
    setRunning(view_, result == Status::Ok);
    if (result == Status::Ok) {
      loop_->scanDue = true;
    } else {
      scheduler_.startTimer(records_->retryTimer, kMonitorTask, monitor_event::kRetry, config_.retryInterval);
    }
  }
  Status startScan() { return driver_.startScan(records_->measurement); }
  // Pack storage (storage_mode.hpp): the scans it skips; a load or a fault ends it. No-ops without it.
  bool storageTick() { return storage_.tick(); }
  void storageScanned() { storage_.scanned(); }
  ScanVerdict scanFinished(Status result, Instant) {
    sample_.last = result;
    // Implausible: the gauge answered (PEC-checked, or read twice alike) with a value its inputs cannot give
    // (drivers/bq4050/limits.hpp): a cell above 5 V, what the cell below an open sense wire reads, or a
    // temperature an open thermistor line gives. An open sense line, not a lost link: open_wire, no
    // re-probe.
    const bool openWire = result == Status::Implausible;
    if (result == Status::Ok) {
      const auto& m = records_->measurement;
      const auto cells = m.cells();
      for (size_t c = 0; c < cells.size(); ++c)
        sample_.cellMv[c] = cells[c];
      sample_.tempDeciK[0] = m.temperatureDeciK;
      sample_.takenAt = m.takenAt;
      sample_.valid = true;
      view_.hasCurrent = true;
      view_.currentMa = m.currentMa;
      // The gauge's own state of charge: RelativeStateOfCharge in % and its capacities in mAh
      // (BatteryMode[CAPM] = 0, SLUUAQ3A 0x03: the reset value, which this image never changes).
      view_.soc.set(static_cast<uint16_t>(m.rsocPercent * 10U), m.remainingCapacity, m.fullChargeCapacity,
                    SocBasis::Gauge);
      view_.deviceBlocks = blockedPaths(m);
    }
    return {.newData = result == Status::Ok || openWire, .failed = result != Status::Ok, .counts = !openWire};
  }
  // A refused word: the readings cannot show the open wire (summarize() found none in them), so say it here.
  // An open line at the bottom or the top leaves one cell reading about 0 V, which the gauge accepts and
  // summarize() itself flags (kCellFloorMv): that flag stays.
  void afterSummarize() {
    if (sample_.last == Status::Implausible) view_.totals.openWire = true;
  }
  // Three failed scans in a row: the gauge may have reset or gone; probe it again now, then every interval.
  void recover() {
    setRunning(view_, false);
    loop_->retryDue = true;
  }

  // What changes, zero at construction (one block, no per-member start-up code), after the references; the
  // gauge driver last.
  struct Records {
    Bq4050Stats stats;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    drivers::bq4050::DeviceInfo info;
    drivers::bq4050::Measurement measurement;
  };
  sched::Scheduler& scheduler_;
  const Bq4050AppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  Zeroed<Records> records_;
  [[no_unique_address]] StorageState storage_;
  drivers::bq4050::Gauge driver_;
};
using Bq4050Monitor = MonitorTask<Bq4050Device>;
extern template class MonitorTask<Bq4050Device>;  // bq4050_app.cpp

// The composition (app_core.hpp): the gauge's monitor, and protection with the fault output (one output opens
// both paths: FaultPinActuator; the current faults recover on time). Inline: an image constructs it once, and
// the constructor is then stores only.
class Bq4050App : public AppCore<FaultPinActuator, CanPublisher> {
 public:
  struct Io {
    hal::I2cBus& bus;
    hal::CanBus& can;
    hal::DigitalOut& faultOut;
    hal::SystemControl& system;
  };
  static constexpr const ProtectionConfig& kLimits = kSingleOutputLimits;

  Bq4050App(sched::Scheduler& scheduler, const Io& io, const Bq4050AppConfig& config)
      : AppCore(scheduler, kLimits, config.scanPeriod, io.can, io.system, CanLayout::Native, io.faultOut,
                true),
        monitor_(scheduler, io.bus, config, *addressOf(sample_), *view_, *status_) {
    // The view's shape; the rest of it (and the publish status) starts zero, as Zeroed blocks do.
    view_->cellsPerBoard = config.gauge.cells;
    view_->tempsPerBoard = 1;
    view_->boards = {&*sample_, 1};
  }
  void start() { startAll(monitor_, nullptr, kStorageBuilt ? &monitor_.storage() : nullptr); }

  const Bq4050Monitor& monitor() const { return monitor_; }

 private:
  Bq4050Monitor monitor_;  // last but the sample: its gauge driver's buffers would push the rest far away
  Zeroed<BoardSample> sample_;
};

}  // namespace fw::app
