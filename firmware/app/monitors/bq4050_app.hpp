// The application of the lp-mspm0g3507-bq4050 image: a BQ4050 gas gauge on SMBus, CAN out.
//
// Tasks (priority = TaskId, higher first):
//   2 protection   firmware limits on every new scan and every scan period; fault output pin (PB26)
//   1 monitor      probe (device type, PEC detection), then a scan every scan period; after three failed
//                  scans in a row it probes again at once (the gauge may have reset: PEC and device type are
//                  checked anew), and while probes fail, again every retry interval
//   0 publisher    CAN frames (native layout; the gauge's relative state of charge goes in PackSummary)
// The gauge protects the pack with its own FETs (SafetyStatus); the firmware layer adds its limits and acts
// through the fault output, as on the BQ79616 image.
#pragma once

#include <cstdint>

#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "drivers/bq4050/gauge.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq4050AppConfig {
  drivers::bq4050::GaugeConfig gauge{};
  Duration scanPeriod = ms(100);
  Duration retryInterval = ms(100);  // between failed probes (a probe of an absent gauge is a few NACKs)
};

struct Bq4050Stats {
  uint32_t scans = 0;
  uint32_t scanFailures = 0;
  uint32_t probes = 0;
};

class Bq4050Monitor final : public sched::Task {
 public:
  static constexpr sched::TaskId kId = 1;

  // Inline: an image constructs it once, and the constructor is then stores only.
  Bq4050Monitor(sched::Scheduler& scheduler, hal::I2cBus& bus, const Bq4050AppConfig& config,
                BoardSample& sample, PackView& view, sched::TaskId protection, sched::TaskId publisher)
      : protection_(protection),
        publisher_(publisher),
        scheduler_(scheduler),
        config_(config),
        sample_(sample),
        view_(view),
        gauge_(bus, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer}, config.gauge) {}

  void start() {
    scheduler_.addTask(kId, *this, {}, true);
    scheduler_.startTimer(records_.scanTimer, kId, kScanTick, config_.scanPeriod, config_.scanPeriod);
    scheduler_.post(kId, kRetry);
  }
  void run(sched::EventMask events) override;

  const drivers::bq4050::Gauge& gauge() const { return gauge_; }
  const Bq4050Stats& stats() const { return records_.stats; }
  const drivers::bq4050::DeviceInfo& info() const { return records_.info; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kScanTick = 0x4, kRetry = 0x8;
  inline void finished(Instant now);  // inline (.cpp): one caller, folded into it

  // What changes, zero at construction (one block each, no per-member start-up code): the small fields
  // first (Cortex-M0+ byte loads reach only 31 bytes past the object's address), the records after the
  // references, the gauge driver last.
  struct Flags {
    bool probed;
    bool scanning;
    bool scanDue;
    bool retryDue;  // start() posts kRetry: the first probe starts at once
    uint8_t failedInRow;
  };
  struct Records {
    Bq4050Stats stats;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    drivers::bq4050::DeviceInfo info;
    drivers::bq4050::Measurement measurement;
  };
  Flags flags_{};
  sched::TaskId protection_;
  sched::TaskId publisher_;
  sched::Scheduler& scheduler_;
  const Bq4050AppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  Records records_{};
  drivers::bq4050::Gauge gauge_;
};

class Bq4050App {
 public:
  struct Io {
    hal::I2cBus& bus;
    hal::CanBus& can;
    hal::DigitalOut& faultOut;
  };
  static constexpr sched::TaskId kProtectionId = 2;
  static constexpr sched::TaskId kPublisherId = 0;

  // Inline: an image constructs it once, and the constructor is then stores only.
  Bq4050App(sched::Scheduler& scheduler, const Io& io, const Bq4050AppConfig& config)
      : view_{.cellsPerBoard = config.gauge.cells, .tempsPerBoard = 1, .boards = {&sample_, 1}},
        plan_(view_, status_, kDefaultLimits.staleAfter),
        actuator_(io.faultOut, true),
        protection_(scheduler, kProtectionId, kDefaultLimits, view_, status_, actuator_, config.scanPeriod),
        publisher_(scheduler, kPublisherId, io.can, plan_, CanLayout::Native, ms(100), 10),
        monitor_(scheduler, io.bus, config, sample_, view_, kProtectionId, kPublisherId) {}
  void start() {
    protection_.start();
    monitor_.start();
    publisher_.start();
  }

  const PackView& pack() const { return view_; }
  const PublishStatus& status() const { return status_; }
  const ProtectionTask& protection() const { return protection_; }
  const Bq4050Monitor& monitor() const { return monitor_; }
  const CanPublisher& publisher() const { return publisher_; }

 private:
  BoardSample sample_{};
  PackView view_;
  PublishStatus status_;
  FramePlan plan_;
  FaultPinActuator actuator_;
  ProtectionTask protection_;
  CanPublisher publisher_;
  Bq4050Monitor monitor_;  // last: its gauge driver's buffers would push the rest far away
};

}  // namespace fw::app
