// The application of the lp-mspm0g3507-bq79616 image: a BQ79616 daisy chain on a UART, CAN out.
//
// Tasks (priority = TaskId, higher first):
//   3 protection   firmware limits on every new scan, on nFAULT at once, and every scan period; fault output
//   2 monitor      the chain: bring-up, a scan every scanPeriod (at once on an nFAULT edge), recovery
//   1 publisher    CAN frames: native cycles every 100 ms / 1 s, or seed 001's layout after each scan
// The same object runs on the LaunchPad and in bms-sim (host BSP, chain emulator); only Io differs.
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
  CanLayout layout = CanLayout::Native;
  Duration recoveryInterval = s(1);  // at most one recovery attempt per interval
};

struct MonitorStats {
  uint32_t scans = 0;         // scans completed
  uint32_t scanFailures = 0;  // scans that did not validate every device
  uint32_t earlyScans = 0;    // scans started by the fault line
  uint32_t scanOverruns = 0;  // scan periods that came while the previous scan was still running
  uint32_t bringUps = 0;
  uint32_t recoveries = 0;  // recovery operations run
  Duration lastScan{};      // duration of the last scan
  Duration worstScan{};
};

class Bq79616Monitor final : public sched::Task {
 public:
  static constexpr sched::TaskId kId = 2;

  Bq79616Monitor(sched::Scheduler& scheduler, hal::Uart& uart, hal::EdgeInput& nfault,
                 const Bq79616AppConfig& config, std::span<BoardSample> samples, int16_t (*raw)[16],
                 PackView& view, sched::TaskId protection, sched::TaskId publisher);

  void start();
  void run(sched::EventMask events) override;

  const drivers::bq79616::Chain& chain() const { return chain_; }
  const MonitorStats& stats() const { return stats_; }
  bool running() const { return phase_ == Phase::Running; }

 private:
  static constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kFault = 0x4, kScanTick = 0x8, kRetry = 0x10;
  enum class Phase : uint8_t { BringUp, Running, Waiting, Recovering };
  enum class Op : uint8_t { None, BringUp, Scan, Recovery };
  void startNext(Instant now);
  void finished(Instant now);
  void publishScan();

  sched::Scheduler& scheduler_;
  const Bq79616AppConfig& config_;
  drivers::bq79616::Chain chain_;
  hal::EdgeInput& nfault_;
  std::span<BoardSample> samples_;
  int16_t (*raw_)[16];
  PackView& view_;
  sched::TaskId protection_;
  sched::TaskId publisher_;
  sched::Timer scanTimer_;
  sched::Timer retryTimer_;
  Phase phase_ = Phase::BringUp;
  Op op_ = Op::None;
  bool scanDue_ = false;
  bool retryDue_ = true;  // bring-up starts at once
  bool early_ = false;
  uint8_t failedInRow_ = 0;
  Instant opStarted_{};
  Instant lastRecovery_{};
  bool recoveredOnce_ = false;
  MonitorStats stats_;
  drivers::bq79616::DeviceRecord records_[drivers::bq79616::kMaxDevices];
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

  Bq79616App(sched::Scheduler& scheduler, const Io& io, const Bq79616AppConfig& config);
  void start();

  const PackView& pack() const { return view_; }
  const ProtectionTask& protection() const { return protection_; }
  const CanPublisher& publisher() const { return publisher_; }
  const Bq79616Monitor& monitor() const { return monitor_; }
  const PublishStatus& status() const { return status_; }

 private:
  Bq79616AppConfig config_;
  ProtectionConfig limits_;
  BoardSample samples_[drivers::bq79616::kMaxDevices];
  int16_t raw_[drivers::bq79616::kMaxDevices][16];
  PackView view_;
  PublishStatus status_;
  FramePlan plan_;
  FaultPinActuator actuator_;
  ProtectionTask protection_;
  Bq79616Monitor monitor_;
  CanPublisher publisher_;
};

}  // namespace fw::app
