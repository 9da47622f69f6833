// The application of the lp-mspm0g3507-bq4050 image: a BQ4050 gas gauge on SMBus, CAN out.
//
// Tasks (priority = TaskId, higher first):
//   3 protection   firmware limits on every new scan and every scan period; fault output pin (PB26)
//   2 monitor      probe (device type, PEC detection), then a scan every scan period; after three failed
//                  scans in a row it probes again, at most once per retry interval
//   1 publisher    CAN frames (native layout; the gauge's relative state of charge goes in PackSummary)
// The gauge protects the pack with its own FETs (SafetyStatus); the firmware layer adds its limits and acts
// through the fault output, as on the BQ79616 image.
#pragma once

#include <cstdint>

#include "app/can_publisher.hpp"
#include "app/frame_plan.hpp"
#include "app/pack_view.hpp"
#include "app/protection_task.hpp"
#include "drivers/bq4050/gauge.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/i2c_bus.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq4050AppConfig {
  drivers::bq4050::GaugeConfig gauge{};
  Duration scanPeriod = ms(100);
  Duration retryInterval = s(1);
};

struct Bq4050Stats {
  uint32_t scans = 0;
  uint32_t scanFailures = 0;
  uint32_t probes = 0;
};

class Bq4050Monitor final : public sched::Task {
 public:
  static constexpr sched::TaskId kId = 2;

  Bq4050Monitor(sched::Scheduler& scheduler, hal::I2cBus& bus, const Bq4050AppConfig& config,
                BoardSample& sample, PackView& view, sched::TaskId protection, sched::TaskId publisher);

  void start();
  void run(sched::EventMask events) override;

  const drivers::bq4050::Gauge& gauge() const { return gauge_; }
  const Bq4050Stats& stats() const { return stats_; }
  const drivers::bq4050::DeviceInfo& info() const { return info_; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kScanTick = 0x4, kRetry = 0x8;
  void finished(Instant now);

  sched::Scheduler& scheduler_;
  const Bq4050AppConfig& config_;
  drivers::bq4050::Gauge gauge_;
  BoardSample& sample_;
  PackView& view_;
  sched::TaskId protection_;
  sched::TaskId publisher_;
  sched::Timer scanTimer_;
  sched::Timer retryTimer_;
  bool probed_ = false;
  bool scanning_ = false;
  bool scanDue_ = false;
  bool retryDue_ = true;
  uint8_t failedInRow_ = 0;
  Bq4050Stats stats_;
  drivers::bq4050::DeviceInfo info_{};
  drivers::bq4050::Measurement measurement_{};
};

class Bq4050App {
 public:
  struct Io {
    hal::I2cBus& bus;
    hal::CanBus& can;
    hal::DigitalOut& faultOut;
  };
  static constexpr sched::TaskId kProtectionId = 3;
  static constexpr sched::TaskId kPublisherId = 1;

  Bq4050App(sched::Scheduler& scheduler, const Io& io, const Bq4050AppConfig& config);
  void start();

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
  Bq4050Monitor monitor_;
  CanPublisher publisher_;
};

}  // namespace fw::app
