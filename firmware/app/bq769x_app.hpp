// The application of the BQ769x2-family images (lp-mspm0l1306-bq76952, lp-mspm0l1306-bq76907 and
// lp-mspm0g3507-bq76952): one monitor device on I2C, FET control through it, SLCAN or CAN out.
//
// Tasks (priority = TaskId, higher first):
//   3 protection   firmware limits on every new scan, on ALERT at once, and every scan period
//   2 monitor      probe, configuration (one CONFIG_UPDATE, only if the device differs), FET enable, a scan
//                  every scan period; FET commands from protection go ahead of the next scan
//   1 publisher    SLCAN lines (L1306) or CAN frames (G3507)
// ALERT is configured (DefaultAlarmMask) to assert on the device's safety alerts, safety status and
// permanent-fail flags only, so the line itself is a fault signal: protection opens the FETs without waiting
// for a scan, and the scan that follows says which fault it was.
// Bq769xMonitor is a template over the driver class (Bq769x2 or Bq7690x) so each image carries one copy
// of exactly the code it uses.
#pragma once

#include <cstdint>
#include <span>

#include "app/can_publisher.hpp"
#include "app/default_limits.hpp"
#include "app/frame_plan.hpp"
#include "app/pack_view.hpp"
#include "app/protection_task.hpp"
#include "app/slcan_publisher.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "hal/serial.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq769xAppConfig {
  std::span<const drivers::bq769x2::Setting> settings{};  // the CONFIG_UPDATE table applied at start-up
  uint8_t cells = 16;                                     // cells connected
  drivers::bq769x2::MonitorConfig monitor{};
  Duration scanPeriod = ms(100);
  Duration retryInterval = s(1);
};

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

template <class Driver, class Measurement>
class Bq769xMonitor final : public sched::Task, public Actuator {
 public:
  static constexpr sched::TaskId kId = 2;

  template <class... DriverArgs>
  Bq769xMonitor(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert,
                const Bq769xAppConfig& config, BoardSample& sample, PackView& view,
                ProtectionTask& protection, sched::TaskId publisher, sched::EventMask publisherScanDone,
                DriverArgs&&... driverArgs)
      : scheduler_(scheduler),
        driver_(bus, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer},
                static_cast<DriverArgs&&>(driverArgs)..., config.monitor),
        alert_(alert),
        config_(config),
        sample_(sample),
        view_(view),
        protection_(protection),
        publisher_(publisher),
        publisherScanDone_(publisherScanDone) {}

  void start() {
    scheduler_.addTask(kId, *this, {}, true);
    alert_.enable(scheduler_.notifier(kId, kAlert));
    scheduler_.startTimer(scanTimer_, kId, kScanTick, config_.scanPeriod, config_.scanPeriod);
    scheduler_.post(kId, kRetry);
  }

  // Actuator: protection asks for the paths; the FET command goes out as soon as the bus is free.
  bool request(bool chargeOn, bool dischargeOn) override {
    using drivers::bq769x2::FetCommand;
    fetWanted_ = true;
    fet_ = chargeOn && dischargeOn     ? FetCommand::AllOn
           : !chargeOn && !dischargeOn ? FetCommand::AllOff
           : !chargeOn                 ? FetCommand::ChargeOff
                                       : FetCommand::DischargeOff;
    scheduler_.post(kId, kKick);
    return false;
  }

  void run(sched::EventMask events) override {
    const Instant now = scheduler_.clock().now();
    if ((events & driver_.events()) != 0 && driver_.onEvent(events) == drivers::Progress::Done) finished(now);
    if ((events & kAlert) != 0 && phase_ == Phase::Running) {
      ++stats_.alerts;
      scheduler_.post(protection_.id(), ProtectionTask::kFaultLine);
      scanDue_ = true;  // the next scan, right after the FET command, says which fault it was
    }
    if ((events & kScanTick) != 0) {
      scanDue_ = true;
      fetBackoff_ = false;  // a failed FET command is tried again once per scan period
      scheduler_.checkIn(kId);
    }
    if ((events & kRetry) != 0) retryDue_ = true;
    if (!driver_.busy()) startNext(now);
  }

  const Driver& driver() const { return driver_; }
  const Bq769xStats& stats() const { return stats_; }
  bool running() const { return phase_ == Phase::Running; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kAlert = 0x4, kScanTick = 0x8, kRetry = 0x10,
                                    kKick = 0x20;
  enum class Phase : uint8_t { Probe, Configure, FetEnable, Running };
  enum class Op : uint8_t { None, Setup, Scan, Fet };

  void startNext(Instant now) {
    Status s = Status::Busy;
    if (fetWanted_ && !fetBackoff_ && phase_ == Phase::Running) {
      fetWanted_ = false;
      s = driver_.startFet(fet_);
      op_ = Op::Fet;
    } else if (phase_ != Phase::Running) {
      if (scanDue_) {
        scanDue_ = false;  // not measuring yet: protection counts the period as failed (stale, comm loss)
        scheduler_.post(protection_.id(), ProtectionTask::kScanFailed);
      }
      if (!retryDue_) return;
      if (phase_ == Phase::Probe) ++stats_.setupAttempts;
      s = phase_ == Phase::Probe       ? driver_.startProbe(identity_)
          : phase_ == Phase::Configure ? driver_.startConfigure(config_.settings)
                                       : driver_.startFetEnable();
      op_ = Op::Setup;
    } else if (scanDue_) {
      scanDue_ = false;
      s = driver_.startScan(measurement_);
      op_ = Op::Scan;
    }
    if (s != Status::Ok) op_ = Op::None;
    (void)now;
  }

  void finished(Instant now) {
    const Status result = driver_.result();
    const Op op = op_;
    op_ = Op::None;
    if (op == Op::Setup) {
      if (result != Status::Ok) {
        // Start over from the probe after the interval (the device may have reset or be absent).
        phase_ = Phase::Probe;
        retryDue_ = false;
        scheduler_.startTimer(retryTimer_, kId, kRetry, config_.retryInterval);
        return;
      }
      if (phase_ == Phase::Configure) stats_.configWrites = driver_.written();
      phase_ = static_cast<Phase>(static_cast<uint8_t>(phase_) + 1);
      if (phase_ == Phase::Running) scanDue_ = true;
      return;
    }
    if (op == Op::Fet) {
      if (result == Status::Ok) {
        ++stats_.fetCommands;
        protection_.actuated(now);
      } else {
        // The device did not take it (gone, resetting): keep scanning, and try again next period. The
        // device's own protection stays the backstop meanwhile.
        fetWanted_ = true;
        fetBackoff_ = true;
      }
      return;
    }
    if (op != Op::Scan) return;
    ++stats_.scans;
    sample_.attempted = true;
    sample_.last = result;
    if (result == Status::Ok) {
      toSample(measurement_, config_.cells, sample_, view_);
      summarize(view_, now);
      scheduler_.post(protection_.id(), ProtectionTask::kNewData);
      failedInRow_ = 0;
    } else {
      ++stats_.scanFailures;
      summarize(view_, now);
      scheduler_.post(protection_.id(), ProtectionTask::kScanFailed);
      if (++failedInRow_ >= 3) {
        // The device stopped answering or keeps failing: go through probe and configuration again (a
        // device reset loses its RAM configuration), at most once per retry interval.
        phase_ = Phase::Probe;
        failedInRow_ = 0;
        retryDue_ = false;
        scheduler_.startTimer(retryTimer_, kId, kRetry, config_.retryInterval);
      }
    }
    scheduler_.post(publisher_, publisherScanDone_);
  }

  sched::Scheduler& scheduler_;
  Driver driver_;
  hal::EdgeInput& alert_;
  const Bq769xAppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  ProtectionTask& protection_;
  sched::TaskId publisher_;
  sched::EventMask publisherScanDone_;
  sched::Timer scanTimer_;
  sched::Timer retryTimer_;
  Phase phase_ = Phase::Probe;
  Op op_ = Op::None;
  bool scanDue_ = false;
  bool retryDue_ = false;
  bool fetWanted_ = false;
  bool fetBackoff_ = false;
  drivers::bq769x2::FetCommand fet_ = drivers::bq769x2::FetCommand::AllOff;
  uint8_t failedInRow_ = 0;
  Bq769xStats stats_;
  drivers::bq769x2::Identity identity_;
  Measurement measurement_;
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
  static constexpr sched::TaskId kProtectionId = 3;
  static constexpr sched::TaskId kPublisherId = 1;

  template <class Output, class... DriverArgs>
  Bq769xApp(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert, Output& output,
            const Bq769xAppConfig& config, DriverArgs&&... driverArgs)
      : view_{std::span<const BoardSample>(&sample_, 1), config.cells,
              tempsOf(static_cast<Measurement*>(nullptr))},
        plan_(view_, status_, kDefaultLimits.staleAfter),
        protection_(scheduler, kProtectionId, kDefaultLimits, view_, status_, monitor_, config.scanPeriod),
        monitor_(scheduler, bus, alert, config, sample_, view_, protection_, kPublisherId,
                 Publisher::kScanDone, static_cast<DriverArgs&&>(driverArgs)...),
        publisher_(makePublisher(scheduler, kPublisherId, output, plan_)) {}

  void start() {
    protection_.start();
    monitor_.start();
    publisher_.start();
  }

  const PackView& pack() const { return view_; }
  const PublishStatus& status() const { return status_; }
  const ProtectionTask& protection() const { return protection_; }
  const Bq769xMonitor<Driver, Measurement>& monitor() const { return monitor_; }
  const Publisher& publisher() const { return publisher_; }

 private:
  BoardSample sample_{};
  PackView view_;
  PublishStatus status_;
  FramePlan plan_;
  ProtectionTask protection_;
  Bq769xMonitor<Driver, Measurement> monitor_;
  Publisher publisher_;
};

}  // namespace fw::app
