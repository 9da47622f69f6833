// Persistence: what an image keeps across a reset in the RecordStore (records.hpp): the protection log, the
// fault record, the settings written by command and the state of charge, with the start-up restore and the
// scheduling of every flash write and erase.
//
// Contract
// - start(info), once at start-up before the tasks start (thread mode, interrupts may be on): restores the
//   store, reads the protection log and the fault record, and writes a new Fault record when this reset was
//   a watchdog expiry (RSTCAUSE WWDT0: Bsp, code kWatchdogCode) or a fault the previous run recorded in SRAM
//   (info.faultValid: its module and line). It fills info: logEntries (the restored log's entries),
//   faultSource (LastReset: the fault of this reset, now in flash; Stored: no fault this reset, the newest
//   Fault record of an earlier run, whose module and code it puts in faultModule / faultLine; None), so the
//   Startup message publishes them. A write that finds no erased sector erases one first (at start-up only:
//   at most one sector erase, <= 20 ms, SLASEX5C section 7.7, before protection runs). It also restores the
//   settings (LimitSettings::restore: each limit checked as a command's write is; a refused one is counted,
//   settingsRefused(), and keeps its default) and keeps the newest state-of-charge record for
//   restoredSoc(), which the image hands to its state of charge before the monitor starts.
// - evaluated() (TripObserver, from the protection task after each evaluation): a newly tripped fault is
//   added to the log in RAM (the oldest entry dropped when full) with the seconds since start-up and the
//   value that tripped it (PackView: the extreme, the current, the device's blocks). Nothing is written
//   there: when the protection task reports `settled` (a scan ended, no path request pending) and the store
//   has work (a log to write, a sector to erase), it posts the lowest-priority task, which calls step().
//   The same evaluation notes new settings (LimitSettings::changes(): a command's write applied) and a state
//   of charge to keep: a counted one (not the gauge's, which keeps its own) that moved kSocStep from the
//   stored value, or moved at all and the stored one is kSocMaxAgeS old.
// - step() (BackgroundWork, from that task): one flash job per call: the log, else the settings, else the
//   state of charge, else one sector erase; the next settled evaluation posts it again if work is left. A
//   write that finds no erased sector (Busy) erases one and writes in the next step. So every program and
//   erase runs after the scan's bus work and the FET request, from the task that runs only when protection,
//   the monitor and the publisher have nothing to do. A step runs with interrupts masked (PRIMASK): a
//   fault-line edge that comes during it stays pending, and the flash driver's wait, which runs through
//   every program and erase, acts on it at once (the MSPM0 driver's watch: bsp/mspm0/flashctl.hpp); the
//   interrupt and protection run when the step returns (store/README.md "In the images").
// - beforeReset() (BackgroundWork, from the command task just before a commanded reset, the paths off):
//   writes at once what is waiting and a state of charge that moved at all since it was stored, through
//   the steps the lowest task would run (at most six: three record writes, each possibly after an erase).
// - Results: lastStatus() is the store's status of the last write or erase (Ok before any).
// - Thread mode only; not reentrant.
#pragma once

#include <array>
#include <cstdint>

#include "app/command/settings.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/protection_task.hpp"
#include "app/publish/publish_status.hpp"
#include "app/store/record_store.hpp"
#include "app/store/records.hpp"
#include "app/tasks.hpp"
#include "core/zeroed.hpp"
#include "hal/flash.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::store {

// The fault code of a watchdog expiry in the Fault record and the Startup message (next to HardFault's
// 0xFFFE and abort's 0xFFFD, bsp/mspm0/fault.hpp).
inline constexpr uint16_t kWatchdogCode = 0xFFFC;
// RSTCAUSE.ID of a WWDT0 violation (MSPM0 TRM SLAU846B Table 2-12 / SLAU847D Table 2-9; hw_sysctl
// RSTCAUSE_ID 0x0E): a BOOTRST, which clears SRAM, so only the reset cause tells of it.
inline constexpr uint8_t kResetCauseWatchdog = 0x0E;

class Persistence final : public TripObserver, public BackgroundWork {
 public:
  // A state-of-charge record when the value moved this far from the stored one (0.1 %)...
  static constexpr uint16_t kSocStep = 10;
  // ... or moved at all and the stored one is this old (s).
  static constexpr uint32_t kSocMaxAgeS = 600;

  // `pack` gives the values trips are logged with and the state of charge; `settings` the limits restored
  // and kept; step() runs in kCommandTask on command_event::kStore.
  Persistence(hal::FlashStorage& flash, sched::Scheduler& scheduler, const PackView& pack,
              command::LimitSettings& settings)
      : store_(flash), scheduler_(scheduler), pack_(pack), settings_(settings) {}

  void start(StartupInfo& info);
  void evaluated(FaultMask newlyTripped, bool settled, Instant now) override;
  void step() override;
  void beforeReset() override;

  // After start(): the kept state of charge (false: none), and how many kept settings were refused.
  bool restoredSoc(uint16_t& permille) const;
  uint8_t settingsRefused() const { return state_->settingsRefused; }

  // The protection log as it is kept (decoded from its stored form): for tests and tools.
  ProtectionLogRecord log() const;
  Status lastStatus() const { return state_->last; }
  const RecordStore& store() const { return store_; }

 private:
  void restoreSettingsAndSoc();
  enum class Job : uint8_t { None, Log, Settings, Soc };
  bool hasWork() const { return nextJob() != Job::None || store_.needsErase(); }
  Job nextJob() const;
  // Writes the record of `job` (the store's status); done() ends the job, written or failed.
  Status write(Job job);
  void done(Job job);
  bool socMoved(uint16_t step) const;
  void repost();
  void addTrip(FaultId id, uint32_t uptimeS);
  // The newest record of type `t` decoded into `r`; false (r unchanged) when there is none or it does not
  // decode (another length: another format version).
  template <class Record>
  bool read(RecordType t, Record& r) const;
  uint32_t uptimeS(Instant now);

  // What changes at run time, all zero at construction (core/zeroed.hpp): no log, no time, Status::Ok.
  struct State {
    // The log in its stored form (records.hpp): written as it is, no encoding on the way to the flash.
    std::array<uint8_t, ProtectionLogRecord::kBytes> log;
    uint32_t seconds;  // since start-up, counted from the evaluations' instants
    uint32_t subUs;    // microseconds past seconds
    Instant lastEvaluation;
    uint32_t socStoredAtS;  // when the stored state of charge was written (0: before this start-up)
    uint16_t socStored;     // the stored state of charge (0.1 %), valid with socKept
    bool socKept;
    bool socDirty;
    bool logDirty;
    bool settingsDirty;
    uint8_t settingsSeen;  // LimitSettings::changes() when the settings were last noted
    uint8_t settingsRefused;
    bool posted;
    Status last;
  };

  RecordStore store_;
  sched::Scheduler& scheduler_;
  const PackView& pack_;
  command::LimitSettings& settings_;
  Zeroed<State> state_;
};

}  // namespace fw::app::store
