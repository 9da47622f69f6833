// MonitorTask<Device>: the one loop every monitor task runs (set up, scan every scan period, validate,
// publish, recover), with the device as the varying part, as LibreSolar's bms_ic API gives every monitor IC
// one interface. The loop:
//   run()        a command posted (BQ769x FET request) -> the device takes it (a scan in progress gives way);
//                the scan period -> a scan is due, and the task checks in with the watchdog supervisor; the
//                retry timer -> set-up is due; the driver's events -> finished(); the fault line while
//                running -> the device (BQ79616: early scan; only a device with kFaultLineToo gets it). With
//                the driver idle: startNext().
//   startNext()  not running: the period counts as failed (kScanFailed to protection: comm loss and stale
//                data go on), and when set-up is due the device starts its next set-up step. Running: a
//                waiting device command first, else a scan when one is due.
//   finished()   set-up and command results go to the device; a scan's result becomes samples and view
//                fields (the device), then the statistics, the failure count (kFailuresBeforeRecovery failed
//                scans in a row: the device's recovery), summarize(), kNewData and/or kScanFailed to
//                protection (both when some boards validated and others failed) and the device's scan-done
//                event to the publisher.
// The fault line (ALERT/nFAULT) is wired to the protection task itself; the monitor gets it too only where it
// needs it (BQ79616: Scheduler::notifier(a, ea, b, eb)). Protection and the monitor hold no reference to each
// other: the monitor writes the PackView (PackView::monitorRunning, the loop's own running flag, also gates
// the fault line in protection) and posts events by task id.
//
// A Device is a class derived from MonitorBase that provides, in this order of members (small fields first:
// Cortex-M0+ byte loads reach only 31 bytes past the object's address; the driver with its buffers last):
//   scheduler_, view_, records_ (with .stats, a ScanStats, and .scanTimer), driver_ (busy(),
//   result(), onEvent()), and
//   kCommands, kPublisherScanDone      device commands (then commandWaiting(), startCommand(),
//                                      commandFinished(Status), and commandPosted() if anything posts
//                                      kCommand); the publisher's scan-done event (0: none)
//   kFaultLineToo                      the monitor gets the fault line as well (then faultLine())
//   kBalancing                         optional: the device balances (then balanceCheck())
//   scanPeriod(), driverEvents() (constexpr: the events the task gave its driver), firstDataBound() (from
//   power-up: the documented bound of the first bring-up and its first scan; PackView::inStartupGrace()
//   until then or the first scan's result)
//   attachFaultLine(), scanTick()                           optional: a device without them has no such work
//   storageTick() -> bool, storageScanned()                 optional, pack storage (storage_mode.hpp): at
//                                                           each scan period, whether a scan is due; after
//                                                           each validated scan
//   startSetup(), setupFinished(Status)                    set-up steps; setRunning() when done
//   startScan(), scanFinished(Status, Instant) -> ScanVerdict, afterSummarize()
//   recover()                                               after kFailuresBeforeRecovery failed scans
// The concept MonitorDevice (below) states this contract; MonitorTask<Device> requires it. Each image has one
// Device; link-time optimisation folds the hooks into the task (no hand inlining). Thread mode only (the
// task's run()); the fault line's Notify is ISR-safe (Scheduler::post).
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>

#include "app/pack/pack_view.hpp"
#include "app/protection/protection_task.hpp"
#include "app/tasks.hpp"
#include "core/stats.hpp"
#include "core/zeroed.hpp"
#include "drivers/operation.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

// The monitor task's events: the driver's two first (the DriverContext the device gives its driver).
namespace monitor_event {
inline constexpr sched::EventMask kBus = 0x1, kTimer = 0x2, kFaultLine = 0x4, kScanTick = 0x8, kRetry = 0x10,
                                  kCommand = 0x20;
// Balancing: the device posts it to itself after each scan, so the balancing policy runs once protection (the
// higher priority) has evaluated that scan (Device::balanceCheck()).
inline constexpr sched::EventMask kBalance = 0x40;
}  // namespace monitor_event

// Scans that fail in a row before the device's recovery (every device: three).
inline constexpr uint8_t kFailuresBeforeRecovery = 3;

enum class MonitorOp : uint8_t { None, Setup, Scan, Command };

// What the loop counts on every device: the first fields of each device's statistics, which add their own
// (core/stats.hpp: all 0 in a build without them).
struct ScanStats {
  uint32_t scans = 0;         // scans completed (a scan that gave way to a command is not one)
  uint32_t scanFailures = 0;  // scans that did not validate every board
};

// What a finished scan means for the loop (Device::scanFinished()). Bit-fields: one byte, so the verdict
// stays in a register once scanFinished() is folded into the loop.
struct ScanVerdict {
  bool measured : 1 = true;  // false: the scan gave way to a command; nothing is counted or reported
  bool newData : 1 = false;  // a board validated: kNewData to protection (otherwise kScanFailed)
  bool failed : 1 = false;   // counted in stats().scanFailures
  bool counts : 1 = true;    // a failure that counts toward recovery (BQ4050 open wire does not)
};

// The loop's own state, first in every device. Not a Task itself: MonitorTask derives from the device first
// and from sched::Task second. The ABI still places Task (the only base with a vtable) at offset 0, but
// constructs it after the device: its vtable pointer store is then followed at once by MonitorTask's and
// dropped, where a Task constructed before the device's out-of-line driver constructor would keep a
// vtable of its own (12 B) alive. Under link-time optimisation this still pays on the G3507-BQ79616 image
// (24 B, measured); the other images come out the same either way.
class MonitorBase {
 protected:
  // Set-up done (scanning from now) or lost. The flag lives in the PackView only (protection reads it too).
  static void setRunning(PackView& view, bool on) { view.monitorRunning = on; }

  struct Loop {    // zero at construction
    MonitorOp op;  // the driver operation in flight
    bool scanDue;
    bool retryDue;  // start() posts kRetry: set-up starts at once
    uint8_t failedInRow;
  };
  Zeroed<Loop> loop_;
};

// MonitorDevice<D>: the device contract above as a concept, one named part per group of hooks, so a device
// that lacks a hook or gives it another type is told which part fails. The hooks and fields are D's
// protected members (only the task reaches them), so each part is checked from DeviceHooks<D>, a class
// derived from D: there they are visible, as they are to MonitorTask. DeviceHooks is never built.
template <class D>
struct DeviceHooks : D {
  // scheduler_ (sched::Scheduler&), view_ (PackView&), records_ with stats (a ScanStats) and scanTimer, and
  // driver_ with busy(), result() and onEvent(EventMask) -> Progress.
  static consteval bool fieldHooks() {
    return requires(DeviceHooks & d, sched::EventMask e) {
      { d.scheduler_ } -> std::convertible_to<sched::Scheduler&>;
      { d.view_ } -> std::convertible_to<PackView&>;
      { d.records_->stats } -> std::convertible_to<ScanStats&>;
      { d.records_->scanTimer } -> std::convertible_to<sched::Timer&>;
      { d.driver_.busy() } -> std::same_as<bool>;
      { d.driver_.result() } -> std::same_as<Status>;
      { d.driver_.onEvent(e) } -> std::same_as<drivers::Progress>;
    };
  }
  // kCommands, kFaultLineToo (bool), kPublisherScanDone (EventMask), scanPeriod(), firstDataBound()
  // (Duration), driverEvents() (EventMask).
  static consteval bool constantHooks() {
    return requires(DeviceHooks & d) {
      requires std::is_same_v<decltype(D::kCommands), const bool>;
      requires std::is_same_v<decltype(D::kFaultLineToo), const bool>;
      requires std::is_convertible_v<decltype(D::kPublisherScanDone), sched::EventMask>;
      { d.scanPeriod() } -> std::same_as<Duration>;
      { d.firstDataBound() } -> std::same_as<Duration>;
      { DeviceHooks::driverEvents() } -> std::same_as<sched::EventMask>;
    };
  }
  // startSetup(), setupFinished(Status), startScan(), scanFinished(Status, Instant) -> ScanVerdict,
  // afterSummarize(), recover().
  static consteval bool setupScanHooks() {
    return requires(DeviceHooks & d, Status s, Instant now) {
      { d.startSetup() } -> std::same_as<Status>;
      { d.setupFinished(s) } -> std::same_as<void>;
      { d.startScan() } -> std::same_as<Status>;
      { d.scanFinished(s, now) } -> std::same_as<ScanVerdict>;
      { d.afterSummarize() } -> std::same_as<void>;
      { d.recover() } -> std::same_as<void>;
    };
  }
  // With kCommands: commandWaiting(), startCommand(), commandFinished(Status).
  static consteval bool commandHooks() {
    if constexpr (D::kCommands) {
      return requires(DeviceHooks & d, Status s) {
        { d.commandWaiting() } -> std::same_as<bool>;
        { d.startCommand() } -> std::same_as<Status>;
        { d.commandFinished(s) } -> std::same_as<void>;
      };
    } else {
      return true;
    }
  }
  // With kFaultLineToo: faultLine().
  static consteval bool faultLineHook() {
    if constexpr (D::kFaultLineToo) {
      return requires(DeviceHooks & d) {
        d.faultLine();
      };
    } else {
      return true;
    }
  }
  // With kBalancing (optional) true: balanceCheck().
  static consteval bool balancingHook() {
    if constexpr (requires { D::kBalancing; }) {
      if constexpr (D::kBalancing) {
        return requires(DeviceHooks & d) {
          d.balanceCheck();
        };
      }
    }
    return true;
  }
};

template <class D>
concept MonitorDevice = std::derived_from<D, MonitorBase> &&
    DeviceHooks<D>::fieldHooks() && DeviceHooks<D>::constantHooks() && DeviceHooks<D>::setupScanHooks() &&
    DeviceHooks<D>::commandHooks() && DeviceHooks<D>::faultLineHook() && DeviceHooks<D>::balancingHook();

template <MonitorDevice Device>
class MonitorTask final : public Device, public sched::Task {
 public:
  static constexpr sched::TaskId kId = kMonitorTask;
  using Device::Device;

  bool running() const { return this->view_.monitorRunning; }

  // Whether the device balances cells (its kBalancing, and then balanceCheck()); one without it does not.
  static constexpr bool balances() {
    if constexpr (requires { Device::kBalancing; }) {
      return Device::kBalancing;
    } else {
      return false;
    }
  }

  void start() {
    this->view_.startupGrace = true;  // until the first scan's result, or firstDataBound()
    this->view_.firstDataDue = Instant{this->firstDataBound().us};
    this->scheduler_.addTask(kId, *this, {}, true);
    if constexpr (requires(MonitorTask & t) { t.attachFaultLine(); }) this->attachFaultLine();
    // Scans start on the clock's scan-period grid, whatever start-up took: the host build and the image on
    // the twin (which boots for 0.5 ms first) then scan at the same instants and see a scenario the same way.
    this->scheduler_.startTimer(this->records_->scanTimer, kId, monitor_event::kScanTick,
                                untilGrid(this->scheduler_.now(), this->scanPeriod()), this->scanPeriod());
    this->scheduler_.post(kId, monitor_event::kRetry);
  }

  void run(sched::EventMask events) override {
    using namespace monitor_event;
    // The task's own events first, under one test: most runs carry only the driver's. The command first of
    // all, so a scan in progress gives way before the driver starts its next read.
    const sched::EventMask driverEvents = this->driverEvents();
    if ((events & ~driverEvents) != 0) {
      if constexpr (requires(MonitorTask & t) { t.commandPosted(); }) {
        if ((events & kCommand) != 0) this->commandPosted();
      }
      if ((events & kScanTick) != 0) {
        if constexpr (requires(MonitorTask & t) { t.scanTick(); }) this->scanTick();
        bool due = true;  // in pack storage only every few periods
        if constexpr (requires(MonitorTask & t) { t.storageTick(); }) due = this->storageTick();
        this->loop_->scanDue |= due;
        this->scheduler_.checkIn(kId);  // alive and on schedule, whatever the device's state
      }
      if ((events & kRetry) != 0) this->loop_->retryDue = true;
      if constexpr (balances()) {
        if ((events & kBalance) != 0) this->balanceCheck();
      }
    }
    if ((events & driverEvents) != 0 && this->driver_.onEvent(events) == drivers::Progress::Done) finished();
    if constexpr (Device::kFaultLineToo) {  // after finished(): a set-up that just ended counts as running
      if ((events & kFaultLine) != 0 && this->view_.monitorRunning) this->faultLine();
    }
    if (!this->driver_.busy()) startNext();
  }

 private:
  void startNext() {
    auto& loop = *this->loop_;
    Status s = Status::Busy;
    MonitorOp op = MonitorOp::Setup;
    if (!this->view_.monitorRunning) {
      if (loop.scanDue) {
        // Nothing measured until set-up is done: protection counts the period as failed, except while the
        // first bring-up runs within its bound.
        loop.scanDue = false;
        if (!this->view_.inStartupGrace(this->scheduler_.now()))
          this->scheduler_.post(kProtectionTask, ProtectionTask::kScanFailed);
      }
      if (!loop.retryDue) return;
      s = this->startSetup();
    } else if (commandWaiting()) {
      s = this->startCommand();
      op = MonitorOp::Command;
    } else if (loop.scanDue) {
      loop.scanDue = false;
      s = this->startScan();
      op = MonitorOp::Scan;
    }
    loop.op = s == Status::Ok ? op : MonitorOp::None;
  }

  // The command hooks, for a device with kCommands only (a device without them has none to write).
  bool commandWaiting() const {
    if constexpr (Device::kCommands) {
      return this->Device::commandWaiting();
    } else {
      return false;
    }
  }
  Status startCommand() {
    if constexpr (Device::kCommands) {
      return this->Device::startCommand();
    } else {
      return Status::Busy;  // not reached: commandWaiting() is false
    }
  }

  void finished() {
    auto& loop = *this->loop_;
    const Instant now = this->scheduler_.now();
    const Status result = this->driver_.result();
    const MonitorOp op = loop.op;
    loop.op = MonitorOp::None;
    if (op == MonitorOp::Setup) return this->setupFinished(result);
    if constexpr (Device::kCommands) {
      if (op == MonitorOp::Command) return this->commandFinished(result);
    }
    if (op != MonitorOp::Scan) return;
    const ScanVerdict v = this->scanFinished(result, now);
    if (!v.measured) return;
    auto& stats = this->records_->stats;
    if (kStats) ++stats.scans;
    if (!v.failed) {
      loop.failedInRow = 0;
    } else {
      if (kStats) ++stats.scanFailures;
      if (v.counts && ++loop.failedInRow >= kFailuresBeforeRecovery) {
        loop.failedInRow = 0;
        this->recover();
      }
    }
    summarize(this->view_, now);
    if constexpr (requires(MonitorTask & t) { t.storageScanned(); }) {
      if (v.newData) this->storageScanned();
    }
    this->afterSummarize();
    this->view_.startupGrace = false;  // the first result is in: protection judges the data from now on
    // A scan that validated some boards and failed on others is both: new data, and a failed attempt
    // (protection's failure rate counts it).
    this->scheduler_.post(kProtectionTask,
                          (v.newData ? ProtectionTask::kNewData : 0) |
                              (!v.newData || (v.failed && v.counts) ? ProtectionTask::kScanFailed : 0));
    if constexpr (Device::kPublisherScanDone != 0)
      this->scheduler_.post(kPublisherTask, Device::kPublisherScanDone);
  }
};

}  // namespace fw::app
