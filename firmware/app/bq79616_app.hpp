// The application of the lp-mspm0g3507-bq79616 image: a BQ79616 daisy chain on a UART, CAN out.
//
// Tasks (priority = TaskId, higher first):
//   3 protection   firmware limits on every new scan, on nFAULT at once, and every scan period; fault output
//   2 monitor      the chain: bring-up, a scan every scanPeriod (at once on an nFAULT edge), recovery
//   1 publisher    CAN frames: native cycles every 100 ms / 1 s, or seed 001's layout after each scan
// The same objects run on the LaunchPad and in bms-sim (host BSP, chain emulator); only Io differs.
// The large buffers (per-device records and samples, about 7 KB for 64 devices) live in Bq79616Storage,
// which the caller provides as a zero-initialised static object: no start-up code fills them.
#pragma once

#include <cstdint>

#include "app/can_publisher.hpp"
#include "app/frame_plan.hpp"
#include "app/pack_view.hpp"
#include "app/protection_task.hpp"
#include "drivers/bq79616/chain.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/uart.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq79616AppConfig {
  drivers::bq79616::ChainConfig chain{};
  Duration scanPeriod = ms(100);
  const ProtectionConfig* limits = nullptr;  // null: kDefaultLimits (default_limits.hpp)
  CanLayout layout = CanLayout::Native;
  Duration recoveryInterval = s(1);  // at most one recovery attempt per interval
};

struct Bq79616Storage {
  BoardSample samples[drivers::bq79616::kMaxDevices];
  int16_t raw[drivers::bq79616::kMaxDevices][drivers::bq79616::kCellsPerDevice];
  drivers::bq79616::DeviceRecord records[drivers::bq79616::kMaxDevices];
};

struct MonitorStats {
  uint32_t scans = 0;         // scans completed
  uint32_t scanFailures = 0;  // scans that did not validate every device
  uint32_t earlyScans = 0;    // scans started by the fault line
  uint32_t scanOverruns = 0;  // scan periods that came while the previous scan was still running
  uint32_t recoveries = 0;    // bring-up and recovery operations run
  Duration lastScan{};        // duration of the last scan
};

class Bq79616Monitor final : public sched::Task {
 public:
  static constexpr sched::TaskId kId = 2;

  Bq79616Monitor(sched::Scheduler& scheduler, hal::Uart& uart, hal::EdgeInput& nfault,
                 const Bq79616AppConfig& config, Bq79616Storage& storage, PackView& view,
                 sched::TaskId protection, sched::TaskId publisher);

  void start();
  void run(sched::EventMask events) override;

  const drivers::bq79616::Chain& chain() const { return chain_; }
  const MonitorStats& stats() const { return stats_; }
  bool running() const { return phase_ == Phase::Running; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kFault = 0x4, kScanTick = 0x8, kRetry = 0x10;
  enum class Phase : uint8_t { BringUp, Running, Recovering };
  void startNext(Instant now);
  void finished(Instant now);
  void publishScan(Instant now);

  sched::Scheduler& scheduler_;
  const Bq79616AppConfig& config_;
  drivers::bq79616::Chain chain_;
  hal::EdgeInput& nfault_;
  Bq79616Storage& store_;
  PackView& view_;
  sched::TaskId protection_;
  sched::TaskId publisher_;
  sched::Timer scanTimer_;
  sched::Timer retryTimer_;
  Phase phase_ = Phase::BringUp;
  bool scanning_ = false;
  bool scanDue_ = false;
  bool retryDue_ = true;  // bring-up starts at once
  bool early_ = false;
  uint8_t failedInRow_ = 0;
  Instant opStarted_{};
  MonitorStats stats_;
  drivers::bq79616::ScanSummary summary_;
};

class Bq79616App {
 public:
  struct Io {
    hal::Uart& uart;
    hal::EdgeInput& nfault;
    hal::CanBus& can;
    hal::DigitalOut& faultOut;
  };
  static constexpr sched::TaskId kProtectionId = 3;
  static constexpr sched::TaskId kPublisherId = 1;

  Bq79616App(sched::Scheduler& scheduler, const Io& io, const Bq79616AppConfig& config,
             Bq79616Storage& storage);
  void start();

  const PackView& pack() const { return view_; }
  const ProtectionTask& protection() const { return protection_; }
  const CanPublisher& publisher() const { return publisher_; }
  const Bq79616Monitor& monitor() const { return monitor_; }
  const PublishStatus& status() const { return status_; }

 private:
  Bq79616AppConfig config_;
  const ProtectionConfig& limits_;
  PackView view_;
  PublishStatus status_;
  FramePlan plan_;
  FaultPinActuator actuator_;
  ProtectionTask protection_;
  Bq79616Monitor monitor_;
  CanPublisher publisher_;
};

}  // namespace fw::app
