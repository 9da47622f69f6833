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
// Balancing (app/balancing, built with FW_BQ769X_BALANCE): after each scan the monitor posts itself kBalance,
// so the policy runs once protection has evaluated that scan; its mask goes to CB_ACTIVE_CELLS as a device
// command behind any FET command and after the scan (startBalance: write and read request, three short
// transactions), again every Variant::cbRefreshS, and is read back after the next scan (startBalanceCheck);
// only a read-back that matches counts as balancing (BalancingStatus). A FET request that opens a path stops
// balancing right after the FET command, without waiting for the policy.
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
#include <type_traits>

#include "app/balancing/balancing_config.hpp"
#include "app/balancing/balancing_policy.hpp"
#include "app/balancing/balancing_status.hpp"
#include "app/command/commands.hpp"
#include "app/config.hpp"
#include "app/monitors/app_core.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "app/monitors/fet_mailbox.hpp"
#include "app/monitors/monitor_task.hpp"
#include "app/monitors/storage_mode.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/slcan_publisher.hpp"
#include "app/soc/soc.hpp"
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
static_assert(!kStorageBuilt || drivers::bq769x2::kSleepControl,
              "pack storage allows the device's SLEEP through the driver (FW_BQ769X_SLEEP)");
static_assert(!kConfigUpdate || drivers::bq769x2::kConfigPaths,
              "the start-up CONFIG_UPDATE needs the link's configuration paths (FW_BQ769X_CONFIG_PATHS)");
static_assert(!kSoc || drivers::bq769x2::kCharge,
              "the state of charge counts the device's accumulated charge (FW_BQ769X_CHARGE)");
// FW_SOC=0: no state of charge is kept (nor its RAM); the view's StateOfCharge stays not available.
struct NoStateOfCharge {
  constexpr NoStateOfCharge(const SocConfig&, CounterFamily, int32_t) {}
  void update(const SocInputs&) {}
  bool known() const { return false; }
  uint16_t permille() const { return 0; }
  uint32_t remainingMah() const { return 0; }
  uint32_t capacityMah() const { return 0; }
  SocBasis basis() const { return SocBasis::Unknown; }
};
using SocState = std::conditional_t<kSoc, StateOfCharge, NoStateOfCharge>;

struct Bq769xAppConfig {
  drivers::bq769x2::SettingsTable settings{};  // the CONFIG_UPDATE table applied at start-up (packed)
  uint8_t cells = 16;                          // cells connected
  drivers::bq769x2::MonitorConfig monitor{};
  Duration scanPeriod = kScanPeriod;  // the default limits' debounce counts assume it (default_limits.hpp)
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
  // State of charge (app/soc, built with FW_SOC) from the device's accumulated charge: the pack's
  // parameters (its pack file's state_of_charge) and the device's current LSB in 0.1 mA (its user-amps unit).
  // nullptr (or FW_SOC=0): none computed, published as not available.
  const SocConfig* soc = nullptr;
  int32_t currentLsbTenthMa = 10;
  // Pack storage (FW_STORAGE, storage_mode.hpp): the pack file's `storage`; scanEvery 0: none. Nothing in a
  // build without it.
  [[no_unique_address]] StorageSettings storage{};
};

// Statistics (core/stats.hpp: all 0 in a build without them).
struct Bq769xStats : ScanStats {
  uint32_t fetCommands = 0;    // FET commands completed
  uint32_t setupAttempts = 0;  // probe/configure/FET-enable sequences started
  uint8_t configWrites = 0;    // settings the last configuration actually wrote (0: the device matched)
};

// The balancing rules of a BQ769x2-family device (BalancingPolicy): at most kBq769x2BalanceCells /
// kBq7690xBalanceCells at once (bq769x_settings.hpp says why), neighbours only on the BQ7690x (SLUAAP7
// section 3; BQ769x2: E2E 1505209). Slot 0 of the view is the internal (die) temperature on both.
constexpr BalancingRules balancingRules(const drivers::bq769x2::Variant& v) {
  return {v.cbAdjacent ? kBq7690xBalanceCells : kBq769x2BalanceCells, v.cbAdjacent, 0x01};
}

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
               const PublishStatus& status, DriverArgs&&... driverArgs)
      : scheduler_(scheduler),
        alert_(alert),
        config_(config),
        sample_(sample),
        view_(view),
        fet_(fet),
        status_(status),
        policy_(kDefaultBalancing, balancingRules(variantOf(driverArgs...))),
        soc_(config.soc != nullptr ? *config.soc : kNoSoc, kCounterFamily, config.currentLsbTenthMa),
        storage_(config.storage, view, status),
        driver_(bus, scheduler.clock(),
                drivers::DriverContext{scheduler, kMonitorTask, monitor_event::kBus, monitor_event::kTimer},
                static_cast<DriverArgs&&>(driverArgs)..., config.monitor) {}

  const Driver& driver() const { return driver_; }
  const Bq769xStats& stats() const { return records_->stats; }
  // The driver's variant from its constructor arguments: the BQ7690x front end takes one, the BQ769x2's is
  // fixed.
  static constexpr const drivers::bq769x2::Variant& variantOf() { return drivers::bq769x2::kBq76952; }
  static constexpr const drivers::bq769x2::Variant& variantOf(const drivers::bq769x2::Variant& v) {
    return v;
  }
  // Balancing: the command interface's entry (BalancingPolicy::setMode) and what is published.
  BalancingPolicy& balancing() { return policy_; }
  const BalancingStatus& balancingStatus() const { return records_->balance; }
  // The state of charge (restore(): the record store's saved value).
  SocState& stateOfCharge() { return soc_; }
  const SocState& stateOfCharge() const { return soc_; }
  // Pack storage: the command interface's entry (StorageMode::request).
  StorageState& storage() { return storage_; }

 protected:
  static constexpr bool kCommands = true;
  static constexpr bool kBalancing = drivers::bq769x2::kBalance;
  static constexpr CounterFamily kCounterFamily =
      std::is_same_v<Measurement, drivers::bq769x2::Bq7690xMeasurement> ? CounterFamily::Bq7690x
                                                                        : CounterFamily::Bq769x2;
  static constexpr SocConfig kNoSoc{};
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
  // A failed FET or balancing command is tried again once per scan period.
  void scanTick() {
    flags_->fetBackoff = flags_->balanceBackoff = false;
    if (kStorageBuilt) storage_.sleep.backoff = false;
  }

  // Pack storage (storage_mode.hpp): the scans it skips, and the device's SLEEP following it (SLEEP_ENABLE
  // in storage where the pack allows it, SLEEP_DISABLE when leaving).
  bool storageTick() requires kStorageBuilt {
    const bool due = storage_.tick();
    syncSleep();
    return due;
  }
  void storageScanned() requires kStorageBuilt {
    storage_.scanned();
    syncSleep();
  }
  void syncSleep() {
    if (kStorageBuilt && storage_.deviceSleep() != storage_.sleep.allowed) storage_.sleep.wanted = true;
  }
  Status startSleep() {
    storage_.sleep.wanted = false;
    storage_.sleep.command = true;
    storage_.sleep.sending = storage_.deviceSleep();
    const Status s = driver_.startSleep(storage_.sleep.sending);
    if (s != Status::Ok) {
      storage_.sleep.command = false;
      storage_.sleep.wanted = storage_.sleep.backoff = true;
    }
    return s;
  }
  void sleepFinished(Status result) {
    storage_.sleep.command = false;
    if (result == Status::Ok) {
      storage_.sleep.allowed = storage_.sleep.sending;
      syncSleep();  // storage may have changed its mind meanwhile
    } else {
      storage_.sleep.wanted = storage_.sleep.backoff = true;  // again next scan period
    }
  }

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
    // A balancing command gives way as a scan does (at its next transaction).
    if (loop_->op == MonitorOp::Scan || (kBalancing && flags_->balancing)) driver_.yieldScan();
    loop_->scanDue = true;
    // A path opened: protection acts on a fault, so balancing stops right after the FET command.
    if (kBalancing && flags_->fet != drivers::bq769x2::FetCommand::AllOn) stopBalancing();
  }
  // The FET command first; balancing only once the scan due has run (it never delays one).
  bool commandWaiting() const {
    return (flags_->fetWanted && !flags_->fetBackoff) ||
           (kStorageBuilt && storage_.sleep.wanted && !storage_.sleep.backoff) ||
           (kBalancing && !loop_->scanDue && !flags_->balanceBackoff &&
            (flags_->balanceWanted || flags_->checkWanted));
  }
  Status startCommand() {
    const bool fet = flags_->fetWanted && !flags_->fetBackoff;
    if (kStorageBuilt && !fet && storage_.sleep.wanted && !storage_.sleep.backoff) return startSleep();
    if (kBalancing && !fet) return startBalancing();
    flags_->fetWanted = false;
    return driver_.startFet(flags_->fet);
  }
  void commandFinished(Status result) {
    if (kStorageBuilt && storage_.sleep.command) return sleepFinished(result);
    if (kBalancing && flags_->balancing) return balancingFinished(result);
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
      forgetBalancing();           // set up again: a reset stopped whatever balanced
      setRunning(view_, true);
      loop_->scanDue = true;
      flags_->fetWanted =
          flags_->fetRequested;  // protection's last request, again: the device may have reset
      if (kStorageBuilt) {
        storage_.sleep.allowed = false;  // the set-up sent SLEEP_DISABLE: storage allows it again if it wants
        syncSleep();
      }
      return;
    }
    // Without the start-up CONFIG_UPDATE the probe is followed by FET enable.
    flags_->step = static_cast<Step>(static_cast<uint8_t>(flags_->step) +
                                     (!kConfigUpdate && flags_->step == Step::Probe ? 2 : 1));
  }
  // A balancing read-back waits in the device's subcommand window: the scan leaves the accumulated charge out
  // then (the device's counter runs on; the next scan's charge includes it).
  Status startScan() {
    const bool readBackWaits = kBalancing && (flags_->checkPending || flags_->checkWanted);
    return driver_.startScan(records_->measurement, !readBackWaits);
  }
  ScanVerdict scanFinished(Status result, Instant) {
    if (result == Status::Aborted)
      return {.measured = false};  // gave way to a FET command: not a measurement
    sample_.last = result;
    if (result == Status::Ok) {
      toSample(records_->measurement, config_.cells, sample_, view_);
      flags_->socDue = true;
      // The device reset since the set-up: set it up again now (the measurement itself is valid). Not while
      // storage allows SLEEP: a reset is then not told apart (the device's own protections run on; the
      // set-up that follows leaving storage restores what a reset lost).
      if (records_->measurement.reg.batteryStatus.sleep_en() && !(kStorageBuilt && storage_.sleep.allowed)) {
        setRunning(view_, false);
        loop_->retryDue = true;
      }
    }
    return {.newData = result == Status::Ok, .failed = result != Status::Ok};
  }
  // Balancing runs after protection has seen this scan (monitor_task.hpp, kBalance).
  void afterSummarize() {
    if constexpr (kSoc)
      if (config_.soc != nullptr && flags_->socDue) updateSoc();
    if constexpr (kBalancing) scheduler_.post(kMonitorTask, monitor_event::kBalance);
  }
  // The scan's totals and the device's charge counter into the state of charge, published in the view
  // (PackSummary.StateOfCharge, the StateOfCharge message) once known.
  void updateSoc() {
    flags_->socDue = false;
    const PackTotals& t = view_.totals;
    const drivers::bq769x2::ChargeCounter& c = records_->measurement.charge;
    SocInputs in{
        .now = t.takenAt,
        .currentMa = view_.currentMa,
        .maxCellMv = t.extreme[kMaxCell],
        .minCellMv = t.extreme[kMinCell],
        .avgCellMv = static_cast<int16_t>(t.packMv > 0 ? static_cast<uint32_t>(t.packMv) / config_.cells : 0),
        .cells = t.complete && !t.openWire,
        .counted = c.valid};
    if (c.valid)
      in.count = kCounterFamily == CounterFamily::Bq769x2 ? bq769x2Count(c.raw) : bq7690xCount(c.raw);
    soc_.update(in);
    view_.soc.set(soc_.permille(), soc_.remainingMah(), soc_.capacityMah(), soc_.basis());
  }
  // The device stopped answering or keeps failing: go through probe and configuration again, starting with a
  // probe at the next scan period.
  void recover() { retryLater(config_.scanPeriod); }

  // Balancing (kBalancing). Once per scan: the time of what stands confirmed, the policy, and what the device
  // needs: the mask when it differs from the one written or its refresh is due, the read-back of a write.
  void balanceCheck() {
    auto& r = *records_;
    const Instant now = scheduler_.now();
    // A write's read-back waits for the scan after it: the result is long ready (BQ7690x: 2 ms) and the read
    // costs no wait.
    flags_->checkWanted = flags_->checkWanted || flags_->checkPending;
    flags_->checkPending = false;
    r.balance.account(1, elapsed(r.lastCheck, now));
    r.lastCheck = now;
    policy_.decide(view_, status_.active, now, {&r.want, 1});
    r.balance.setMode(policy_.mode());
    r.balance.state = policy_.state();
    if (r.want != r.written || (r.written != 0 && isDue(r.refreshAt, now))) flags_->balanceWanted = true;
  }
  // A write (with its read request) when one is wanted, else the read-back of the last one.
  Status startBalancing() {
    auto& r = *records_;
    flags_->balancing = true;
    flags_->checking = !flags_->balanceWanted;
    Status started;
    if (flags_->checking) {
      flags_->checkWanted = false;
      started = driver_.startBalanceCheck();
    } else {
      // A new write: the read-back of an earlier one is moot (and this one's waits for the next scan, its
      // result not being ready before: an immediate read finds no echo and wrote again).
      flags_->balanceWanted = flags_->checkWanted = false;
      r.sending = r.want;
      started = driver_.startBalance(r.sending);
    }
    if (started != Status::Ok) {  // not started (the rules already hold the mask): again next scan period
      flags_->balancing = false;
      flags_->balanceWanted = flags_->balanceBackoff = true;
    }
    return started;
  }
  void balancingFinished(Status result) {
    auto& r = *records_;
    flags_->balancing = false;
    const Instant now = scheduler_.now();
    const bool check = flags_->checking;
    flags_->checking = false;
    if (!check) {
      if (result == Status::Ok) {
        // Written: balancing runs (or stopped) from now; its read-back follows the next scan.
        r.written = r.sending;
        r.refreshAt = now + s(driver_.variant().cbRefreshS);
        flags_->checkPending = true;
      } else {
        // Gave way to a FET command (Aborted), or the bus failed: write again (the next period for a
        // failure).
        flags_->balanceWanted = true;
        flags_->balanceBackoff = result != Status::Aborted;
        if (result != Status::Aborted) r.balance.cells[0] = 0;  // not known any more
      }
      return;
    }
    if (result == Status::Ok || result == Status::VerifyFailed) {
      r.balance.cells[0] = driver_.balanced();
      if (result == Status::VerifyFailed) {
        // The device did not take it (a rule, its temperature limits, CB_NO_CMD): nothing asked for a while.
        // The policy asks for nothing during its back-off: only what the device kept is stopped (writing
        // the refused mask again at once doubled every refused write).
        policy_.refused(now);
        r.want = 0;
        r.written = driver_.balanced();
        flags_->balanceWanted = r.written != 0;
      }
      return;
    }
    // Another subcommand ran since the write (a FET command): write again; the bus failed: next period.
    r.balance.cells[0] = 0;
    flags_->balanceWanted = true;
    flags_->balanceBackoff = result != Status::EchoMismatch;
  }
  // A path opened: nothing balances from the next command on.
  void stopBalancing() {
    records_->want = 0;
    if (records_->written != 0) flags_->balanceWanted = true;
  }
  void forgetBalancing() {
    if constexpr (!kBalancing) return;
    records_->written = 0;
    records_->balance.cells[0] = 0;
    flags_->balanceWanted = flags_->checkWanted = flags_->checkPending = flags_->checking = false;
  }

  // Starts over from the probe after `wait` (the device may have reset or be absent; a reset loses its RAM
  // configuration).
  void retryLater(Duration wait) {
    setRunning(view_, false);
    forgetBalancing();
    flags_->step = Step::Probe;
    loop_->retryDue = false;
    scheduler_.startTimer(records_->retryTimer, kMonitorTask, monitor_event::kRetry, wait);
  }

  // What changes, zero at construction (one block each, no per-member start-up code): the small fields
  // first (Cortex-M0+ byte loads reach only 31 bytes past the object's address), the records after the
  // references, the driver with its buffers last. Still pays under link-time optimisation: the flags after
  // the references are +20..+32 B on the BQ769x-family images (measured).
  struct Flags {
    Step step;  // the next set-up step (Probe while running)
    bool fetWanted;
    bool fetRequested;  // protection has made a request (fet is its latest)
    bool fetBackoff;
    drivers::bq769x2::FetCommand fet;  // meaningful while fetWanted
    bool balancing;                    // the command in flight is a balancing one
    bool checking;                     // ... the read-back (set when a write ends, until its read-back ends)
    bool balanceWanted;                // the mask must be written (changed, refresh due, or written again)
    bool checkPending;                 // a write ended: its read-back is due after the next scan
    bool checkWanted;                  // the last write's read-back is due
    bool balanceBackoff;               // a balancing command failed on the bus: again next scan period
    bool socDue;                       // a scan validated: the state of charge counts it after summarize
  };
  struct Records {
    Bq769xStats stats;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    drivers::bq769x2::Identity identity;
    uint16_t want;     // the policy's mask
    uint16_t sending;  // the mask of the write in flight
    uint16_t written;  // the last mask the device took a write of (its read-back decides what is published)
    Instant refreshAt;
    Instant lastCheck;
    BalancingStatus balance;
    Measurement measurement;
  };
  Zeroed<Flags> flags_;
  sched::Scheduler& scheduler_;
  hal::EdgeInput& alert_;
  const Bq769xAppConfig& config_;
  BoardSample& sample_;
  PackView& view_;
  FetMailbox& fet_;
  const PublishStatus& status_;
  BalancingPolicy policy_;
  Zeroed<Records> records_;
  SocState soc_;
  [[no_unique_address]] StorageState storage_;
  Driver driver_;
};
template <class Driver, class Measurement, sched::EventMask kPublisherScanDone>
using Bq769xMonitor = MonitorTask<Bq769xDevice<Driver, Measurement, kPublisherScanDone>>;

// The composition (app_core.hpp): one board, its monitor, and protection with the FET actuator (the mailbox
// both tasks hold: the FETs switch through the monitor, and through CFETOFF/DFETOFF where wired). `output` is
// a CanBus (G3507) or a SerialPort (L1306: SLCAN out and in).
template <class Driver, class Measurement, class Publisher>
class Bq769xApp : public AppCore<FetMailbox, Publisher> {
  using Core = AppCore<FetMailbox, Publisher>;

 public:
  template <class Output, class... DriverArgs>
  Bq769xApp(sched::Scheduler& scheduler, hal::I2cBus& bus, hal::EdgeInput& alert, Output& output,
            hal::SystemControl& system, const Bq769xAppConfig& config, DriverArgs&&... driverArgs)
      : Core(scheduler, kDefaultLimits, config.scanPeriod, output, system, CanLayout::Native, scheduler,
             config.chargeOffPin, config.dischargeOffPin),
        monitor_(scheduler, bus, alert, config, *addressOf(sample_), *this->view_, this->actuator_,
                 *this->status_, static_cast<DriverArgs&&>(driverArgs)...) {
    // The view's shape; the rest of it (and the publish status) starts zero, as Zeroed blocks do.
    PackView& view = *this->view_;
    view.cellsPerBoard = config.cells;
    view.tempsPerBoard = tempsOf(static_cast<Measurement*>(nullptr));
    view.hasFetStatus = true;  // every scan reads the FETs' state back
    view.boards = {&*sample_, 1};
    if constexpr (drivers::bq769x2::kBalance) view.balancing = &monitor_.balancingStatus();
  }

  void start() {
    this->startAll(monitor_, drivers::bq769x2::kBalance ? &monitor_.balancing() : nullptr,
                   kStorageBuilt ? &monitor_.storage() : nullptr);
  }

  using Monitor = Bq769xMonitor<Driver, Measurement, Publisher::kScanDone>;
  const Monitor& monitor() const { return monitor_; }
  // The command interface's entry to balancing, and the state of charge.
  BalancingPolicy& balancing() { return monitor_.balancing(); }
  SocState& stateOfCharge() { return monitor_.stateOfCharge(); }

 private:
  Monitor monitor_;
  Zeroed<BoardSample> sample_;
};

}  // namespace fw::app
