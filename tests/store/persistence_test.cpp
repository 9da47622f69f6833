// Persistence (app/store/persistence.hpp) on the host flash model: the start-up restore and fault record,
// the protection log written only from the lowest-priority task after protection settled, and every erase
// there too.
#include "app/store/persistence.hpp"

#include <gtest/gtest.h>

#include <array>

#include "app/protection/default_limits.hpp"
#include "core/assert.hpp"
#include "sim/sim_flash.hpp"
#include "sim/sim_irq.hpp"

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
  explicit Boot(bsp::host::SimFlash& flash) : persist(flash, scheduler, pack, settings), task(persist) {
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
  fw::app::command::LimitSettings settings{fw::app::kDefaultLimits};
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

// The flash behind the store, noting whether interrupts were masked at each program and erase.
class MaskNotingFlash final : public fw::hal::FlashStorage {
 public:
  explicit MaskNotingFlash(bsp::host::SimFlash& flash)
      : FlashStorage(flash.read().data(), flash.sectorCount()), flash_(flash) {}
  int masked = 0, unmasked = 0;

 private:
  fw::Status doErase(uint32_t sector) override {
    note();
    return flash_.erase(sector);
  }
  fw::Status doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) override {
    note();
    return flash_.program(offset, word);
  }
  void note() { ++(bsp::host::simIrq().masked() ? masked : unmasked); }
  bsp::host::SimFlash& flash_;
};

// A step (one job: here an erase, then the write of a trip that compacts) runs with interrupts masked from
// its start to its end, so a fault-line edge between two word programs stays pending until the flash driver's
// wait sees it (bsp/mspm0/flashctl.hpp) instead of running a handler whose task then waits for the step.
TEST(Persistence, EveryStepRunsWithInterruptsMasked) {
  bsp::host::SimFlash sim(2);
  MaskNotingFlash flash(sim);
  FixedClock clock;
  fw::sched::Scheduler scheduler{clock};
  fw::app::PackView pack{};
  fw::app::command::LimitSettings settings{fw::app::kDefaultLimits};
  Persistence persist(flash, scheduler, pack, settings);
  LowestTask task(persist);
  scheduler.addTask(fw::app::kCommandTask, task);
  StartupInfo info{kPor, false, 0, 0};
  persist.start(info);
  for (uint32_t s = 0; s < 100 && sim.eraseCount() < 2; ++s) {  // trips until the store has erased twice
    persist.evaluated(fw::app::bit(FaultId::CellOvervoltage), true, at(s));
    while (scheduler.dispatchOne()) {
    }
  }
  EXPECT_EQ(sim.eraseCount(), 2U);
  EXPECT_GE(flash.masked, 40);
  EXPECT_EQ(flash.unmasked, 0);
  EXPECT_FALSE(bsp::host::simIrq().masked()) << "the mask ends with the step";
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

// --- the settings written by command and the state of charge
// ------------------------------------------------

using fw::app::SocBasis;
using fw::app::command::kSettingCount;
using fw::app::command::SettingSource;
using fw::app::store::RecordType;

constexpr uint8_t kCellOvTrip = 0, kCellOvClear = 1, kOcdTrip = 6, kUtcClear = 15;

// A command's write, applied at the scan boundary as the protection task does, then that scan's evaluation.
void commandWrite(Boot& r, uint8_t id, int32_t value, Instant now) {
  ASSERT_EQ(r.settings.write(id, value), fw::app::command::Result::Accepted);
  r.settings.apply();
  r.persist.evaluated(0, true, now);
}

void setSoc(Boot& r, uint16_t permille, SocBasis basis = SocBasis::Ocv) {
  r.pack.soc.set(permille, 2500U * permille / 1000, 2500, basis);
}

TEST(Persistence, SettingsWrittenByCommandAreRestoredAfterAReset) {
  bsp::host::SimFlash flash(4);
  {
    Boot r(flash);
    r.start({kPor, false, 0, 0});
    const uint32_t programs = flash.programCount();
    r.persist.evaluated(0, true, at(1));
    EXPECT_EQ(r.runAll(), 0) << "no command, nothing to keep";
    commandWrite(r, kOcdTrip, -20000, at(2));
    commandWrite(r, kCellOvTrip, 4200, at(3));
    EXPECT_EQ(flash.programCount(), programs) << "nothing written from the protection task";
    EXPECT_EQ(r.runAll(), 1);
    EXPECT_GT(flash.programCount(), programs);
    EXPECT_EQ(r.persist.lastStatus(), fw::Status::Ok);
  }
  Boot r(flash);  // power cycle
  r.start({kPor, false, 0, 0});
  EXPECT_EQ(r.persist.settingsRefused(), 0);
  EXPECT_EQ(r.settings.read(kOcdTrip), -20000);
  EXPECT_EQ(r.settings.read(kCellOvTrip), 4200);
  EXPECT_EQ(r.settings.limits().rules[0].trip, 4200) << "in effect before protection's first evaluation";
  EXPECT_EQ(r.settings.source(kOcdTrip), SettingSource::Flash);
  EXPECT_EQ(r.settings.source(kUtcClear), SettingSource::Flash);  // the whole record was kept
  EXPECT_EQ(r.settings.read(kUtcClear), fw::app::kDefaultLimits.rules[11].clear);
  // A restore is not a change: nothing is written again until a command writes.
  const uint32_t programs = flash.programCount();
  r.persist.evaluated(0, true, at(1));
  EXPECT_EQ(r.runAll(), 0);
  EXPECT_EQ(flash.programCount(), programs);
  commandWrite(r, kOcdTrip, -25000, at(2));
  EXPECT_EQ(r.settings.source(kOcdTrip), SettingSource::Command);
  EXPECT_EQ(r.runAll(), 1);
  Boot again(flash);
  again.start({kPor, false, 0, 0});
  EXPECT_EQ(again.settings.read(kOcdTrip), -25000);
}

// Values kept in flash are checked exactly as a command's write: a value outside its range, or a clear value
// on the unsafe side of its trip value, is refused (the pair whole), counted, and never applied.
TEST(Persistence, AKeptSettingThatACommandCouldNotWriteIsRefusedCountedAndNeverApplied) {
  bsp::host::SimFlash flash(4);
  fw::app::store::SettingsRecord kept;
  const fw::app::command::LimitSettings defaults(fw::app::kDefaultLimits);
  for (uint8_t id = 0; id < kSettingCount; ++id)
    kept.value[id] = defaults.read(id);
  kept.value[kCellOvTrip] = 4300;  // past the default 4250 mV: loosens protection
  kept.value[kOcdTrip] = -20000;   // in range, but its clear value (7) below it:
  kept.value[kOcdTrip + 1] = -25000;
  kept.value[kUtcClear] = 2900;  // a good pair: utc trip default 2732, clear 2900 (0.1 K)
  {
    fw::app::store::RecordStore store(flash);
    ASSERT_EQ(store.restore(), fw::Status::Ok);
    std::array<uint8_t, fw::app::store::SettingsRecord::kBytes> b;
    encode(kept, b);
    ASSERT_EQ(store.write(static_cast<uint8_t>(RecordType::Settings), b), fw::Status::Ok);
  }
  fw::app::command::LimitSettings probe(fw::app::kDefaultLimits);
  EXPECT_EQ(probe.write(kCellOvTrip, 4300), fw::app::command::Result::OutOfRange)
      << "a command is refused too";
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  EXPECT_EQ(r.persist.settingsRefused(), 4) << "cell_ov and ocd, each pair whole";
  EXPECT_EQ(r.settings.read(kCellOvTrip), 4250);
  EXPECT_EQ(r.settings.read(kCellOvClear), defaults.read(kCellOvClear));
  EXPECT_EQ(r.settings.read(kOcdTrip), defaults.read(kOcdTrip));
  EXPECT_EQ(r.settings.read(kOcdTrip + 1), defaults.read(kOcdTrip + 1));
  EXPECT_EQ(r.settings.limits().rules[0].trip, 4250);
  EXPECT_EQ(r.settings.source(kCellOvTrip), SettingSource::FlashRefused);
  EXPECT_EQ(r.settings.source(kOcdTrip + 1), SettingSource::FlashRefused);
  EXPECT_EQ(r.settings.read(kUtcClear), 2900);
  EXPECT_EQ(r.settings.source(kUtcClear), SettingSource::Flash);
}

TEST(Persistence, TheStateOfChargeIsKeptEachPercentOrAfterTenMinutesAndRestored) {
  bsp::host::SimFlash flash(4);
  {
    Boot r(flash);
    r.start({kPor, false, 0, 0});
    uint16_t kept = 0;
    EXPECT_FALSE(r.persist.restoredSoc(kept));
    r.persist.evaluated(0, true, at(1));
    EXPECT_EQ(r.runAll(), 0) << "not known yet: nothing to keep";
    setSoc(r, 500);
    r.persist.evaluated(0, true, at(2));
    EXPECT_EQ(r.runAll(), 1) << "the first known value";
    uint32_t programs = flash.programCount();
    setSoc(r, 509);
    r.persist.evaluated(0, true, at(3));
    EXPECT_EQ(r.runAll(), 1) << "0.9 %: not yet";
    EXPECT_EQ(flash.programCount(), programs);
    setSoc(r, 490);
    r.persist.evaluated(0, true, at(4));
    EXPECT_EQ(r.runAll(), 2) << "1 % down";
    EXPECT_GT(flash.programCount(), programs);
    programs = flash.programCount();
    setSoc(r, 491);
    r.persist.evaluated(0, true, at(4 + 599));
    EXPECT_EQ(r.runAll(), 2);
    EXPECT_EQ(flash.programCount(), programs);
    r.persist.evaluated(0, true, at(4 + 600));
    EXPECT_EQ(r.runAll(), 3) << "moved and the stored value is 10 minutes old";
    r.persist.evaluated(0, true, at(4 + 1300));
    EXPECT_EQ(r.runAll(), 3) << "not moved: nothing however old";
  }
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  uint16_t kept = 0;
  ASSERT_TRUE(r.persist.restoredSoc(kept));
  EXPECT_EQ(kept, 491);
  // Restored, the state of charge publishes the kept value: nothing to write until it moves.
  setSoc(r, 491, SocBasis::Restored);
  r.persist.evaluated(0, true, at(1));
  EXPECT_EQ(r.runAll(), 0);
}

TEST(Persistence, ACommandedResetKeepsTheStateOfChargeThatMovedAtAllAndWhatWaits) {
  bsp::host::SimFlash flash(2);
  {
    Boot r(flash);
    r.start({kPor, false, 0, 0});
    setSoc(r, 800);
    r.persist.evaluated(0, true, at(1));
    r.runAll();
    setSoc(r, 803);
    ASSERT_EQ(r.settings.write(kOcdTrip, -21000), fw::app::command::Result::Accepted);
    r.settings.apply();
    r.persist.evaluated(0, false, at(2));  // not settled: nothing posted yet
    EXPECT_EQ(r.runAll(), 1);
    r.persist.beforeReset();
    EXPECT_EQ(r.persist.lastStatus(), fw::Status::Ok);
  }
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  uint16_t kept = 0;
  ASSERT_TRUE(r.persist.restoredSoc(kept));
  EXPECT_EQ(kept, 803);
  EXPECT_EQ(r.settings.read(kOcdTrip), -21000);
}

// Sectors fill with state-of-charge records over a long discharge; every one of them is written from the
// lowest task, erases included, and the newest value survives.
TEST(Persistence, AThousandStepsOfChargeCompactAndTheNewestSurvives) {
  bsp::host::SimFlash flash(2);
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  for (uint32_t k = 0; k < 1000; ++k) {
    setSoc(r, static_cast<uint16_t>(k % 2 == 0 ? 1000 - k / 2 * 10 % 1000 : 5));
    const uint32_t erases = flash.eraseCount();
    r.persist.evaluated(0, true, at(k));
    ASSERT_EQ(flash.eraseCount(), erases);
    r.runAll();
    ASSERT_EQ(r.persist.lastStatus(), fw::Status::Ok) << k;
  }
  setSoc(r, 333);
  r.persist.evaluated(0, true, at(2000));
  r.runAll();
  r.persist.evaluated(0, true, at(2001));  // a write that met Busy erased in its step: the next one writes
  r.runAll();
  EXPECT_GT(flash.eraseCount(), 10U);
  Boot again(flash);
  again.start({kPor, false, 0, 0});
  uint16_t kept = 0;
  ASSERT_TRUE(again.persist.restoredSoc(kept));
  EXPECT_EQ(kept, 333);
}

TEST(Persistence, TheGaugesOwnStateOfChargeIsNotKept) {
  bsp::host::SimFlash flash(4);
  Boot r(flash);
  r.start({kPor, false, 0, 0});
  setSoc(r, 700, SocBasis::Gauge);
  r.persist.evaluated(0, true, at(1));
  r.persist.beforeReset();
  EXPECT_EQ(r.runAll(), 0);
  EXPECT_EQ(flash.programCount(), 0U);
}

}  // namespace
