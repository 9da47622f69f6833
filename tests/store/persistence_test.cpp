// Persistence (app/store/persistence.hpp) on the host flash model: the start-up restore and fault record,
// the protection log written only from the lowest-priority task after protection settled, and every erase
// there too.
#include "app/store/persistence.hpp"

#include <gtest/gtest.h>

#include <array>

#include "core/assert.hpp"
#include "sim/sim_flash.hpp"

namespace {

using fw::Instant;
using fw::app::FaultId;
using fw::app::FaultSource;
using fw::app::StartupInfo;
using fw::app::store::Persistence;
using fw::app::store::ProtectionLogRecord;

class FixedClock final : public fw::hal::Clock {
 private:
  Instant doNow() const override { return {}; }
  void doWakeAt(Instant) override {}
};

// Stands in for the command task: the lowest priority, runs the store's step on command_event::kStore.
class LowestTask final : public fw::sched::Task {
 public:
  explicit LowestTask(fw::app::BackgroundWork& work) : work_(work) {}
  void run(fw::sched::EventMask events) override {
    if ((events & fw::app::command_event::kStore) != 0) {
      ++steps;
      work_.step();
    }
  }
  int steps = 0;

 private:
  fw::app::BackgroundWork& work_;
};

// One run of the firmware on the same flash: a fresh Persistence, scheduler and pack, as after a reset.
struct Boot {
  explicit Boot(bsp::host::SimFlash& flash) : persist(flash, scheduler, pack), task(persist) {
    scheduler.addTask(fw::app::kCommandTask, task);
  }
  StartupInfo start(StartupInfo info) {
    persist.start(info);
    return info;
  }
  int runAll() {  // dispatches until nothing is ready; the count of store steps
    while (scheduler.dispatchOne()) {
    }
    return task.steps;
  }
  FixedClock clock;
  fw::sched::Scheduler scheduler{clock};
  fw::app::PackView pack{};
  Persistence persist;
  LowestTask task;
};

constexpr uint8_t kPor = 0x01;          // RSTCAUSE POR (SLAU846B Table 2-12)
constexpr uint8_t kWatchdog = 0x0E;     // BOOTRST, WWDT0
constexpr uint8_t kSysSoftware = 0x1B;  // fw::onFault's SYSRST
constexpr Instant at(uint32_t s) {
  return {s * 1000000U};
}

TEST(Persistence, BlankFlashRestoresNothingAndWritesNothing) {
  bsp::host::SimFlash flash(4);
  Boot r(flash);
  const StartupInfo info = r.start({kPor, false, 0, 0});
  EXPECT_EQ(info.kept.logEntries, 0);
  EXPECT_EQ(info.kept.faultSource, FaultSource::None);
  EXPECT_FALSE(info.faultValid);
  EXPECT_EQ(flash.programCount(), 0U);
  EXPECT_EQ(flash.eraseCount(), 0U);
}

TEST(Persistence, WatchdogResetIsRecordedAndPublishedAfterAPowerCycle) {
  bsp::host::SimFlash flash(4);
  {
    Boot r(flash);
    const StartupInfo info = r.start({kWatchdog, false, 0, 0});
    EXPECT_EQ(info.kept.faultSource, FaultSource::LastReset);
    EXPECT_TRUE(info.faultValid);
    EXPECT_EQ(info.faultModule, static_cast<uint8_t>(fw::Module::Bsp));
    EXPECT_EQ(info.faultLine, fw::app::store::kWatchdogCode);
    EXPECT_EQ(r.persist.lastStatus(), fw::Status::Ok);
  }
  Boot r(flash);  // power cycle: POR, SRAM gone
  const StartupInfo info = r.start({kPor, false, 0, 0});
  EXPECT_EQ(info.kept.faultSource, FaultSource::Stored);
  EXPECT_TRUE(info.faultValid);
  EXPECT_EQ(info.faultModule, static_cast<uint8_t>(fw::Module::Bsp));
  EXPECT_EQ(info.faultLine, fw::app::store::kWatchdogCode);
  std::array<uint8_t, 64> b{};
  uint32_t n = 0;
  ASSERT_EQ(r.persist.store().read(2, b, n), fw::Status::Ok);
  fw::app::store::FaultRecord f{};
  ASSERT_TRUE(fw::app::store::decode(std::span<const uint8_t>(b.data(), n), f));
  EXPECT_EQ(f.resetCause, kWatchdog);
}

TEST(Persistence, SramFaultRecordIsKeptInFlash) {
  bsp::host::SimFlash flash(4);
  {
    Boot r(flash);
    const StartupInfo info = r.start({kSysSoftware, true, 21, 1234});
    EXPECT_EQ(info.kept.faultSource, FaultSource::LastReset);
    EXPECT_EQ(info.faultModule, 21);
    EXPECT_EQ(info.faultLine, 1234);
  }
  Boot r(flash);
  const StartupInfo info = r.start({kPor, false, 0, 0});
  EXPECT_EQ(info.kept.faultSource, FaultSource::Stored);
  EXPECT_EQ(info.faultModule, 21);
  EXPECT_EQ(info.faultLine, 1234);
}

TEST(Persistence, TripIsWrittenOnlyOnceProtectionSettledAndFromTheLowestTask) {
  bsp::host::SimFlash flash(4);
  {
    Boot r(flash);
    r.start({kPor, false, 0, 0});
    r.pack.totals.extreme[fw::app::kMaxCell] = 4321;
    const uint32_t programs = flash.programCount();
    r.persist.evaluated(fw::app::bit(FaultId::CellOvervoltage), false, at(7));  // FET request pending
    EXPECT_EQ(r.runAll(), 0);  // nothing posted, nothing written
    EXPECT_EQ(flash.programCount(), programs);
    r.persist.evaluated(0, true, at(8));        // the next scan ended with the FETs off
    EXPECT_EQ(flash.programCount(), programs);  // still nothing from the protection task itself
    EXPECT_EQ(r.runAll(), 1);
    EXPECT_GT(flash.programCount(), programs);
    EXPECT_EQ(r.persist.lastStatus(), fw::Status::Ok);
  }
  Boot r(flash);  // power cycle
  const StartupInfo info = r.start({kPor, false, 0, 0});
  EXPECT_EQ(info.kept.logEntries, 1);
  EXPECT_EQ(info.kept.faultSource, FaultSource::None);
  const ProtectionLogRecord& log = r.persist.log();
  EXPECT_EQ(log.entry[0].rule, static_cast<uint8_t>(FaultId::CellOvervoltage));
  EXPECT_EQ(log.entry[0].value, 4321);
  EXPECT_EQ(log.entry[0].uptimeS, 7U);
}

TEST(Persistence, LogKeepsTheLastFourTripsAcrossResets) {
  bsp::host::SimFlash flash(4);
  for (uint8_t k = 0; k < 6; ++k) {
    Boot r(flash);
    const StartupInfo info = r.start({kPor, false, 0, 0});
    EXPECT_EQ(info.kept.logEntries, k < 4 ? k : 4);
    r.pack.currentMa = -1000 * k;
    r.persist.evaluated(fw::app::bit(FaultId::DischargeOvercurrent), true, at(k));
    EXPECT_EQ(r.runAll(), 1);
  }
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  const ProtectionLogRecord& log = r.persist.log();
  ASSERT_EQ(log.count, 4);
  for (uint8_t e = 0; e < 4; ++e)
    EXPECT_EQ(log.entry[e].value, -1000 * (e + 2));  // oldest first
}

// Compactions and erases: over many trips the store fills sectors, and every erase happens in a step of the
// lowest task, never in evaluated(); the newest log always survives a reset.
TEST(Persistence, ErasesRunOnlyInTheLowestTask) {
  bsp::host::SimFlash flash(2);
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  uint32_t erasesInSteps = 0;
  for (uint32_t k = 0; k < 200; ++k) {
    const uint32_t before = flash.eraseCount();
    r.pack.totals.extreme[fw::app::kMinCell] = static_cast<int16_t>(2000 + k);
    r.persist.evaluated(fw::app::bit(FaultId::CellUndervoltage), true, at(k));
    ASSERT_EQ(flash.eraseCount(), before) << "erase from the protection task at trip " << k;
    r.runAll();
    erasesInSteps += flash.eraseCount() - before;
    ASSERT_EQ(r.persist.lastStatus(), fw::Status::Ok) << k;
  }
  EXPECT_GT(erasesInSteps, 2U);
  Boot again(flash);
  EXPECT_EQ(again.start({kPor, false, 0, 0}).kept.logEntries, 4);
  EXPECT_EQ(again.persist.log().entry[3].value, 2199);
}

TEST(Persistence, FailingFlashCostsOneJobATripNeverALoop) {
  bsp::host::SimFlash flash(4);
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  flash.failNext(fw::Status::Timeout);
  r.persist.evaluated(fw::app::bit(FaultId::CellOvervoltage), true, at(1));
  EXPECT_EQ(r.runAll(), 1);
  EXPECT_EQ(r.persist.lastStatus(), fw::Status::Timeout);
  // Nothing new: no retry of the write; at most the one erase the store may now want (one job).
  r.persist.evaluated(0, true, at(2));
  const int afterIdle = r.runAll();
  EXPECT_LE(afterIdle, 2);
  r.persist.evaluated(fw::app::bit(FaultId::CellOvervoltage), true, at(3));  // the next trip writes both
  EXPECT_LE(r.runAll(), afterIdle + 2);  // a write, and an erase first if the store was Busy
  EXPECT_EQ(r.persist.lastStatus(), fw::Status::Ok);
  Boot again(flash);
  EXPECT_EQ(again.start({kPor, false, 0, 0}).kept.logEntries, 2);
}

}  // namespace
