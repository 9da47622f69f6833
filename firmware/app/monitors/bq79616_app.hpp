// The application of the lp-mspm0g3507-bq79616 image: a BQ79616 daisy chain on a UART, CAN out.
//
// Tasks (priority = TaskId, higher first; app/tasks.hpp):
//   3 protection   firmware limits on every new scan, on nFAULT at once, and every scan period; fault output
//   2 monitor      MonitorTask<Bq79616Device> (monitor_task.hpp), the chain: bring-up, a scan every
//   scanPeriod (at once on an nFAULT edge), recovery after
//                  three failed scans in a row: at once if a scan validated since the last recovery,
//                  otherwise recoveryInterval later. Recovery climbs the driver's ladder (chain.hpp) from
//                  where it must: from COMM CLEAR after a scan that validated every device in use; one rung
//                  above the last successful rung when the scans failed again since; and from the full
//                  bring-up (WAKE, addressing, configuration, ADC start) after a recovery that failed,
//                  because its WAKE has reset every register. So scans that keep failing always end in a full
//                  bring-up. A bring-up or recovery that found no chain at all is tried again
//                  retryAfterFailure after it ended (the link is down, the bus idle): a healed link is then
//                  up again within about one failed attempt plus one bring-up.
//   1 publisher    CAN frames: native cycles every 100 ms / 1 s, or seed 001's layout after each scan; the
//                  command answers
//   0 command      commands from CAN (app/command)
// Balancing (app/balancing; the device rules: drivers/bq79616/balancer.hpp): after each scan, once protection
// has seen it (kBalance), the policy gives one mask per device. Devices whose mask changed, and every 10 s
// the ones balancing (their timers run 30 s), get their timers and BAL_GO, at most kBalanceAppliesPerScan
// devices a scan period and only after the scan (balancing never delays one); when nothing is wanted any more
// one broadcast stops the whole chain (three frames). BAL_STAT of every device is read once a second while
// anything balances: a device counts as balancing (BalancingStatus) only while it reports CB_RUN, not paused;
// INVALID_CBCONF or ABORTFLT make the policy back off.
// Open wire (drivers/bq79616/open_wire.hpp): the devices' own VC open-wire check over the whole chain after
// the first scan of every bring-up or recovery and then every openWireEvery scans (10: once a second), in the
// balancing slot after a scan, never in place of one (about 6 ms for 2 devices, OpenWireCheck::worstCase()
// at most). Balancing pauses for it (CB_PAUSE, timers held) and resumes after. A cell
// the device reports below the threshold, and the cell above it (both beside the pin that may be open), are
// published as open_wire from every scan until a check says otherwise: their readings are replaced by the
// no-reading 0 mV, which the pack's open-wire rule (pack_view.hpp) turns into open_wire and keeps out of
// every total, exactly as an open wire it sees in the readings itself.
// The same objects run on the LaunchPad and in bms-sim (host BSP, chain emulator); only Io differs.
// The large buffers (per-device records and samples, about 7 KB for 64 devices) live in Bq79616Storage,
// which the caller provides as a zero-initialised static object: no start-up code fills them.
#pragma once

#include <cstdint>

#include "app/balancing/balancing_config.hpp"
#include "app/balancing/balancing_policy.hpp"
#include "app/balancing/balancing_status.hpp"
#include "app/command/commands.hpp"
#include "app/monitors/monitor_task.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "core/zeroed.hpp"
#include "drivers/bq79616/balancer.hpp"
#include "drivers/bq79616/chain.hpp"
#include "drivers/bq79616/open_wire.hpp"
#include "hal/can_bus.hpp"
#include "hal/gpio.hpp"
#include "hal/system.hpp"
#include "hal/uart.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct Bq79616AppConfig {
  drivers::bq79616::ChainConfig chain{};
  Duration scanPeriod = kScanPeriod;  // the default limits' debounce counts assume it (default_limits.hpp)
  const ProtectionConfig* limits = nullptr;  // null: kSingleOutputLimits (default_limits.hpp)
  CanLayout layout = CanLayout::Native;
  Duration recoveryInterval = s(1);      // wait before another recovery while scans keep failing
  Duration retryAfterFailure = ms(100);  // after a bring-up or recovery that brought no chain back
  uint8_t openWireEvery = 10;            // scans between the devices' own open-wire checks (0: never)
};

struct Bq79616Storage {
  BoardSample samples[drivers::bq79616::kMaxDevices];
  int16_t raw[drivers::bq79616::kMaxDevices][drivers::bq79616::kCellsPerDevice];
  drivers::bq79616::DeviceRecord records[drivers::bq79616::kMaxDevices];
  // Balancing, per device: the policy's mask, the mask last written (timers and BAL_GO), BAL_STAT as read.
  uint16_t balanceWant[drivers::bq79616::kMaxDevices];
  uint16_t balanceWritten[drivers::bq79616::kMaxDevices];
  uint8_t balStat[drivers::bq79616::kMaxDevices];
  // The devices' own open-wire verdict, per device (bit c = cell c + 1 below the threshold), as last read.
  uint16_t openWire[drivers::bq79616::kMaxDevices];
  BalancingStatus balancing;
};

// The BQ79616's balancing rules (BalancingPolicy): manual control turns on at most 8 channels and, with
// DEV_CONF[NO_ADJ_CB] (its default), no neighbours (SLUSF21 8.3.3.1.2, SLUSDT5B); both view temperature slots
// are die temperatures (DIETEMP1/2).
inline constexpr BalancingRules kBq79616BalancingRules{drivers::bq79616::Balancer::kMaxChannels, false, 0x03};
// Devices whose timers one scan period writes (3 frames each, about 0.4 ms at 1 Mbaud).
inline constexpr uint8_t kBalanceAppliesPerScan = 8;

struct Bq79616Stats : ScanStats {
  uint32_t earlyScans = 0;       // scans started by the fault line
  uint32_t scanOverruns = 0;     // scan periods that came while the previous scan was still running
  uint32_t recoveries = 0;       // bring-up and recovery operations run
  Duration lastScan{};           // duration of the last scan (its start: ScanSummary::started)
  uint32_t openWireChecks = 0;   // the devices' open-wire checks that gave a verdict
  uint32_t openWireFailed = 0;   // ... that ended without one (the last verdict stands)
  Duration lastOpenWireCheck{};  // duration of the last check
};

// The BQ79616 chain's part of the monitor task (monitor_task.hpp): set-up is the bring-up, and after it the
// recovery ladder from the rung `from` (see the task table above); nFAULT while running starts a scan at once
// (and the chain reads FAULT_SUMMARY in it).
class Bq79616Device : public MonitorBase {
 public:
  // Inline: an image constructs it once, and the constructor is then stores only.
  Bq79616Device(sched::Scheduler& scheduler, hal::Uart& uart, hal::EdgeInput& nfault,
                const Bq79616AppConfig& config, Bq79616Storage& storage, PackView& view,
                const PublishStatus& status)
      : scheduler_(scheduler),
        config_(config),
        nfault_(nfault),
        store_(storage),
        view_(view),
        status_(status),
        policy_(kDefaultBalancing, kBq79616BalancingRules),
        driver_(uart, scheduler.clock(),
                drivers::DriverContext{scheduler, kMonitorTask, monitor_event::kBus, monitor_event::kTimer},
                config.chain),
        balancer_(driver_),
        openWire_(driver_) {}

  const drivers::bq79616::Chain& chain() const { return driver_; }
  const Bq79616Stats& stats() const { return records_->stats; }
  BalancingPolicy& balancing() { return policy_; }  // the command interface's entry

 protected:
  // Commands are the balancing frames (the chain has no FET path: protection drives the fault output itself).
  static constexpr bool kCommands = true;
  static constexpr bool kBalancing = true;
  static constexpr sched::EventMask kPublisherScanDone = CanPublisher::kScanDone;

  Duration scanPeriod() const { return config_.scanPeriod; }
  // The first bring-up and its first scan, from power-up: 120 ms + 15 ms per device. The chain driver waits
  // 69 ms whatever the length (two WAKE pings with tSU(WAKE_SHUT), the 38 ms LPF settling, 4.4 ms after
  // addressing) and 11.6 ms per address slot, one more than the devices (WAKE tone and ACTIVE entry,
  // SLUUC56B), plus its frames (about 1.8 ms per device at 1 Mbaud) and the first scan: computed 81 ms +
  // 13.4 ms per device before the scan. First valid data in bms-sim at 105 / 120 / 320 / 393 / 1023 ms for
  // 1 / 2 / 16 / 21 / 64 devices, within 135 / 150 / 360 / 435 / 1080 ms. Longer than staleAfter from 13
  // devices on: without this grace a chain of 21 or more tripped stale_data at every power-up.
  Duration firstDataBound() const { return ms(120) + ms(15) * config_.chain.devices; }
  // The events this task gave the chain (its DriverContext, and attachFaultLine()): driver_.events(), as
  // constants.
  static constexpr sched::EventMask driverEvents() {
    return monitor_event::kBus | monitor_event::kTimer | monitor_event::kFaultLine;
  }
  // nFAULT goes to protection (which acts on it at once) and to this task (the chain's faultPending: the
  // next scan reads FAULT_SUMMARY; and that scan starts now). The chain arms the pin for this task alone;
  // it is re-armed for both while armed: the two Notifys differ only in their function word (see
  // Scheduler::notifier<a, ea, b, eb>), so an interrupt that reads the Notify half-written posts to this task
  // alone, as an edge just before would have.
  static constexpr bool kFaultLineToo = true;
  void attachFaultLine() {
    hal::EdgeInput& line = nfault_;  // in a register across the call, not loaded again
    driver_.attachFaultLine(line, monitor_event::kFaultLine);
    line.enable(scheduler_.template notifier<kProtectionTask, ProtectionTask::kFaultLine, kMonitorTask,
                                             monitor_event::kFaultLine>());
  }
  // nFAULT while running: a device reports a fault. The next scan (started now) reads FAULT_SUMMARY to say
  // which device and what. During bring-up and recovery the line is expected to be low (devices leave reset
  // with their faults latched until the fault reset), so it is only a fault signal once the chain runs.
  void faultLine() { flags_->early = loop_->scanDue = true; }
  void scanTick() {
    if (loop_->op == MonitorOp::Scan) ++records_->stats.scanOverruns;
  }
  // Balancing work (bq79616_app.cpp), only after the scan due has run.
  bool commandWaiting() const {
    const auto& f = *flags_;
    return !loop_->scanDue &&
           (f.stopWanted || f.openWireDue || (f.dirty != 0 && f.budget != 0) || f.statusWanted);
  }
  inline Status startCommand();                // bq79616_app.cpp
  inline void commandFinished(Status result);  // bq79616_app.cpp
  inline void balanceCheck();                  // bq79616_app.cpp

  // Bring-up the first time; afterwards the recovery ladder (which ends in a full bring-up if it must).
  Status startSetup() {
    loop_->retryDue = false;
    ++records_->stats.recoveries;
    return flags_->broughtUp ? driver_.startRecovery(flags_->from) : driver_.startBringUp();
  }
  // Bring-up or recovery ended: run with the devices that answer, or try again retryAfterFailure later.
  inline void setupFinished(Status result);  // bq79616_app.cpp
  Status startScan() {
    const Status s = driver_.startScan(
        std::span<drivers::bq79616::DeviceRecord>(store_.records, config_.chain.devices), records_->summary);
    if (s == Status::Ok && flags_->early) ++records_->stats.earlyScans;
    flags_->early = false;
    return s;
  }
  inline ScanVerdict scanFinished(Status result, Instant now);  // bq79616_app.cpp
  // Balancing runs after protection has seen this scan (monitor_task.hpp, kBalance).
  void afterSummarize() { scheduler_.post(kMonitorTask, monitor_event::kBalance); }
  // Repeated failures: climb the recovery ladder; at once when scans validated since the last recovery,
  // otherwise at most once per recoveryInterval.
  void recover() {
    setRunning(view_, false);
    scheduler_.startTimer(
        records_->retryTimer, kMonitorTask, monitor_event::kRetry,
        flags_->from == drivers::bq79616::RecoveryLevel{} ? Duration{} : config_.recoveryInterval);
  }

 private:
  // What changes, zero at construction (one block each, no per-member start-up code): the small fields
  // first, the records after the references, the chain driver with its state last.
  enum class BalanceOp : uint8_t { None, Stop, Apply, Status, OpenWire };
  struct Flags {
    bool broughtUp;  // the first bring-up succeeded: set-up is the recovery ladder from now on
    bool early;      // the next scan is started by the fault line
    drivers::bq79616::RecoveryLevel from;  // the rung the next recovery starts at
    BalanceOp op;                          // the balancing operation in flight
    bool stopWanted;                       // one broadcast stop of the whole chain
    bool statusWanted;                     // BAL_STAT of every device
    uint8_t budget;                        // device writes left this scan period
    uint8_t device;                        // the device of the write in flight
    uint16_t sending;                      // ... and its mask
    uint64_t dirty;                        // devices whose timers are to be written (bit d = device d)
    bool openWireDue;                      // the devices' open-wire check runs next
    uint8_t openWireIn;                    // scans until the next check
  };
  struct Records {
    Bq79616Stats stats;
    drivers::bq79616::ScanSummary summary;
    sched::Timer scanTimer;
    sched::Timer retryTimer;
    Instant lastCheck;
    Instant refreshAt;
    Instant statusAt;
    Instant openWireStarted;
  };
  void forgetBalancing();
  void balanceStatusRead();
  void openWireFinished();
  Zeroed<Flags> flags_;

 protected:
  sched::Scheduler& scheduler_;
  const Bq79616AppConfig& config_;
  hal::EdgeInput& nfault_;
  Bq79616Storage& store_;
  PackView& view_;
  const PublishStatus& status_;
  BalancingPolicy policy_;
  Zeroed<Records> records_;
  drivers::bq79616::Chain driver_;
  drivers::bq79616::Balancer balancer_;  // after the chain it drives
  drivers::bq79616::OpenWireCheck openWire_;
};
using Bq79616Monitor = MonitorTask<Bq79616Device>;
extern template class MonitorTask<Bq79616Device>;  // bq79616_app.cpp

class Bq79616App {
 public:
  struct Io {
    hal::Uart& uart;
    hal::EdgeInput& nfault;
    hal::CanBus& can;
    hal::DigitalOut& faultOut;
    hal::SystemControl& system;
  };
  static constexpr sched::TaskId kProtectionId = kProtectionTask;
  static constexpr sched::TaskId kPublisherId = kPublisherTask;

  // `config` and `storage` must outlive the application (they are referenced, not copied).
  // Inline: an image constructs it once, and the constructor is then stores only.
  Bq79616App(sched::Scheduler& scheduler, const Io& io, const Bq79616AppConfig& config,
             Bq79616Storage& storage)
      : plan_(*view_, *status_, limitsOf(config).staleAfter),
        actuator_(io.faultOut, true),
        settings_(limitsOf(config)),
        protection_(scheduler, kProtectionId, settings_.limits(), *view_, *status_, actuator_,
                    config.scanPeriod),
        publisher_(scheduler, kPublisherId, io.can, plan_, config.layout, kFastPeriod, kSlowEvery),
        command_({scheduler, protection_, settings_, io.system, command::kNode}, io.can, publisher_.outbox(),
                 io.system),
        monitor_(scheduler, io.uart, io.nfault, config, storage, *view_, *status_) {
    // The view's shape; the rest of it (and the publish status) starts zero, as Zeroed blocks do.
    view_->cellsPerBoard = config.chain.activeCells;
    view_->tempsPerBoard = 2;
    view_->boards = {storage.samples, config.chain.devices};
    view_->rawCells = &storage.raw[0][0];
    view_->balancing = &storage.balancing;
  }
  void start() {
    protection_.setLimitUpdate(settings_);
    protection_.start();
    monitor_.start();
    publisher_.start();
    command_.setBalancing(monitor_.balancing(), *view_);
    command_.start();
  }

  const PackView& pack() const { return *view_; }
  const ProtectionTask& protection() const { return protection_; }
  const CanPublisher& publisher() const { return publisher_; }
  const command::CommandTask<command::CanLink>& commands() const { return command_; }
  const Bq79616Monitor& monitor() const { return monitor_; }
  const PublishStatus& status() const { return *status_; }
  BalancingPolicy& balancing() { return monitor_.balancing(); }  // the command interface's entry
  // The Startup message (reset cause, version, surviving fault record), once, first in the next cycle.
  void announceStartup(const StartupInfo& info) { plan_.announceStartup(info); }
  // The record store's hooks (FW_RECORD_STORE, app/store/persistence.hpp): trips to `observer`, its flash
  // jobs in the command task. Before start().
  void attachStore(TripObserver& observer, BackgroundWork& work) {
    protection_.setTripObserver(observer);
    command_.setBackground(work);
  }

 private:
  static const ProtectionConfig& limitsOf(const Bq79616AppConfig& config) {
    return config.limits != nullptr ? *config.limits : kSingleOutputLimits;  // one fault output
  }

  Zeroed<PackView> view_;
  Zeroed<PublishStatus> status_;
  FramePlan plan_;
  FaultPinActuator actuator_;
  command::LimitSettings settings_;
  ProtectionTask protection_;
  CanPublisher publisher_;
  command::CommandTask<command::CanLink> command_;
  Bq79616Monitor monitor_;  // last: its chain driver's buffers would push everything after it far away
};

}  // namespace fw::app
