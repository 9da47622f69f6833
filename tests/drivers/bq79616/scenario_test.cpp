// The driver as an application task uses it: a periodic scan every 100 ms, recovery when a scan fails,
// faults injected while it runs, and another task that must keep its period throughout.
#include <gtest/gtest.h>

#include <vector>

#include "bq79616/chain_emulator.hpp"
#include "drivers/bq79616/chain.hpp"
#include "sim/harness.hpp"
#include "sim/uart.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
using fw::ms;
using fw::Status;
using fw::sched::EventMask;

constexpr fw::sched::TaskId kMonitorTask = 3;
constexpr fw::sched::TaskId kOtherTask = 5;
constexpr EventMask kBus = 0x1, kTimer = 0x2, kFault = 0x4, kTick = 0x8;

class MonitorTask final : public fw::sched::Task {
 public:
  enum class Doing { BringUp, Scan, Recover, Idle };

  MonitorTask(fw::sched::Scheduler& sched, bq::Chain& chain) : sched_(sched), chain_(chain) {}

  void start() {
    ASSERT_EQ(chain_.startBringUp(), Status::Ok);
    doing_ = Doing::BringUp;
    sched_.startTimer(tick_, kMonitorTask, kTick, ms(100), ms(100));
  }

  void run(EventMask ev) override {
    if ((ev & chain_.events()) != 0 && chain_.onEvent(ev) == fw::drivers::Progress::Done) {
      const Status s = chain_.result();
      if (doing_ == Doing::Scan) {
        ++scans;
        if (s == Status::Ok) {
          ++goodScans;
        } else {
          failures.push_back(chain_.lastFault());
        }
      }
      if (doing_ == Doing::Recover) recoveries.push_back(s);
      const bool scanFailed = doing_ != Doing::Recover && s != Status::Ok;
      doing_ = Doing::Idle;
      // A failed scan (or bring-up) starts the recovery ladder, at most once a second: a chain that stays
      // degraded (a broken cable) keeps being scanned, reporting the devices that answer, in between.
      if (scanFailed && ticksSinceRecovery_ >= 10 && chain_.startRecovery() == Status::Ok) {
        doing_ = Doing::Recover;
        ticksSinceRecovery_ = 0;
      }
    }
    if ((ev & kTick) != 0) {
      ++ticksSinceRecovery_;
      if (doing_ == Doing::Idle && chain_.startScan(records, summary) == Status::Ok) {
        doing_ = Doing::Scan;
      } else if (doing_ != Doing::Idle) {
        ++busyTicks;
      }
    }
  }

  std::vector<bq::DeviceRecord> records = std::vector<bq::DeviceRecord>(16);
  bq::ScanSummary summary;
  int scans = 0, goodScans = 0, busyTicks = 0;
  std::vector<bq::FaultReport> failures;
  std::vector<Status> recoveries;

 private:
  fw::sched::Scheduler& sched_;
  bq::Chain& chain_;
  fw::sched::Timer tick_;
  Doing doing_ = Doing::Idle;
  int ticksSinceRecovery_ = 10;
};

class OtherTask final : public fw::sched::Task {
 public:
  void run(EventMask) override { ++runs; }
  int runs = 0;
};

TEST(Bq79616Scenario, PeriodicScansSurviveInjectedFaultsAndNeverStallTheScheduler) {
  bsp::host::Harness h;
  bsp::host::SimUart uart(h.clock, h.irq);
  bsp::host::Bq79616ChainEmulator emulator(h.clock, uart, 16);
  bsp::host::SimEdgeInput nfault(h.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true);
  emulator.attachFaultPin(nfault);
  bq::ChainConfig config;
  config.devices = 16;
  bq::Chain chain(uart, h.clock, fw::drivers::DriverContext{h.sched, kMonitorTask, kBus, kTimer}, config);
  MonitorTask monitor(h.sched, chain);
  OtherTask other;
  fw::sched::Timer otherTick;
  h.sched.addTask(kMonitorTask, monitor);
  h.sched.addTask(kOtherTask, other);
  chain.attachFaultLine(nfault, kFault);
  h.sched.startTimer(otherTick, kOtherTask, 0x1, ms(1), ms(1));
  monitor.start();

  h.runFor(ms(1500));  // bring-up and healthy scans
  const int healthy = monitor.goodScans;
  EXPECT_GE(healthy, 5);
  EXPECT_TRUE(monitor.failures.empty());

  emulator.corruptResponse(9, 20, 0x10, 1);  // a transient bit error: retried inside the scan
  h.runFor(ms(500));
  EXPECT_TRUE(monitor.failures.empty());
  EXPECT_GE(chain.stats().crcErrors(), 1u);

  emulator.sleepAll();  // the chain drops into SLEEP (e.g. a communication timeout)
  h.runFor(ms(1000));
  ASSERT_FALSE(monitor.failures.empty());
  EXPECT_EQ(monitor.failures.back().status, Status::NoResponse);
  ASSERT_FALSE(monitor.recoveries.empty());
  EXPECT_EQ(monitor.recoveries.back(), Status::Ok);
  EXPECT_EQ(chain.lastRecovery(), bq::RecoveryLevel::SleepToActive);
  const int afterSleep = monitor.goodScans;

  emulator.breakLinkAbove(11);  // a connector comes loose
  h.runFor(ms(3050));  // from here on checks fall between two 100 ms scans: records are a finished scan
  EXPECT_EQ(chain.devices(), 12) << "recovery re-discovered the devices that still answer";
  EXPECT_EQ(monitor.failures.back().device, 12);
  EXPECT_EQ(monitor.records[11].status, Status::Ok);
  EXPECT_EQ(monitor.records[12].status, Status::NoResponse);
  EXPECT_EQ(monitor.records[12].valid, 0);

  emulator.healLink();
  const size_t failuresBefore = monitor.failures.size();
  h.runFor(ms(3000));
  EXPECT_EQ(chain.devices(), 16) << "the next recovery after a failed scan brings them back";
  EXPECT_GT(monitor.goodScans, afterSleep);
  EXPECT_EQ(monitor.summary.validDevices, 16);
  EXPECT_LE(monitor.failures.size(), failuresBefore + 2);

  // The other task kept its 1 ms period through bring-up, scans and every recovery rung.
  const uint64_t elapsedMs = h.nowUs() / 1000;
  EXPECT_GE(other.runs, static_cast<int>(elapsedMs) - 1);
  EXPECT_EQ(h.sched.stats(kOtherTask).timerOverruns, 0u);
  std::printf("REPORT bq79616.scenario scans=%d good=%d recoveries=%zu retries=%u crc=%u timeouts=%u\n",
              monitor.scans, monitor.goodScans, monitor.recoveries.size(), chain.stats().retries,
              chain.stats().crcErrors(), chain.stats().timeouts());
}

}  // namespace
