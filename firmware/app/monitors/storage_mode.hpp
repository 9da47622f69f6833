// StorageMode: the pack-storage mode of a monitor (issue 32). A pack that rests for weeks needs no 100 ms
// scans: in storage the monitor scans every StorageConfig::scanEvery scan periods (the pack file's
// `storage: scan_period_ms`), and a BQ769x2/BQ7690x device may SLEEP (`device_sleep`), where it measures only
// every Power:Sleep:Voltage Time itself (SLUUBY2B 7.3; SLUUCI8 "SLEEP Mode").
//
// Entering: the StorageMode command (app/command/handler.cpp, refused while a fault is active or the current
// is above the rest threshold), or on its own after `auto_entry_min` minutes at rest (0: by command only).
// Leaving, whatever asked for storage: the command, any active protection fault or a path the device holds
// off (ALERT included: protection turns it into a fault at once, and the monitor checks at every scan
// period), or a scan whose |current| is above the rest threshold. Storage never overrides protection:
// protection evaluates every scan as always, its tick still runs every scan period, and the device's own
// protections stay on (its comparator-based ones run in SLEEP as in NORMAL, SLUUBY2B 7.3), so the firmware's
// detection latency becomes the storage scan period while the device stays the backstop.
// What it publishes honestly (PackView::storage): data counts as stale only after stale_scans storage scan
// periods (plus the device's own interval in SLEEP), and the age of a measurement is its worst case: the
// time since the scan, plus, while the device may SLEEP, the device's own interval (a value read in SLEEP
// may be that old already).
// Thread mode: request() from the command task, the rest from the monitor task.
#pragma once

#include <cstdint>
#include <type_traits>

#include "app/config.hpp"
#include "app/monitors/storage_config.hpp"
#include "app/pack/pack_view.hpp"
#include "app/publish/publish_status.hpp"
#include "core/time.hpp"

namespace fw::app {

// The device's SLEEP as the monitor commands it in storage (Bq769xDevice: SLEEP_ENABLE / SLEEP_DISABLE).
struct SleepCommand {
  bool wanted;   // the device's SLEEP must change
  bool command;  // the command in flight is that one
  bool sending;  // ... allowing SLEEP
  bool allowed;  // the device took SLEEP_ENABLE last (since the set-up)
  bool backoff;  // that command failed: again next scan period
};

// Why a request is refused (the command's answer says it).
enum class StorageRequest : uint8_t { Accepted, Unsupported, FaultActive, NotAtRest };

inline constexpr bool kStorageBuilt = FW_STORAGE != 0;
// A monitor's configuration of it: the pack file's `storage`, nothing in a build without it.
using StorageSettings = std::conditional_t<kStorageBuilt, StorageConfig, NoStorageConfig>;
class StorageMode;
struct NoStorageMode;
using StorageState = std::conditional_t<FW_STORAGE != 0, StorageMode, NoStorageMode>;

#if FW_STORAGE != 0
class StorageMode {
 public:
  StorageMode(const StorageConfig& config, PackView& view, const PublishStatus& status)
      : config_(config), view_(view), status_(status) {
    view_.storage.period = config_.scanPeriod;
  }

  // Command task. Entering needs no active fault, no path held off by the device and the pack at rest (the
  // last scan's current); leaving is always accepted. Takes effect at the monitor's next scan period.
  StorageRequest request(bool enter) {
    if (config_.scanEvery == 0) return StorageRequest::Unsupported;
    if (enter) {
      if (faulted()) return StorageRequest::FaultActive;
      if (!atRest()) return StorageRequest::NotAtRest;
    }
    wanted_ = enter;
    return StorageRequest::Accepted;
  }

  // Monitor task, every scan period: whether a scan is due (every scanEvery periods in storage), after
  // leaving storage on a fault and entering or leaving as asked.
  bool tick() {
    if (config_.scanEvery == 0) return true;
    if (faulted()) wanted_ = false, restPeriods_ = 0;
    if (wanted_ != view_.storage.on) {
      set(wanted_);
      ticksLeft_ = 0;
    }
    // Counted, not timed: an Instant wraps after 71.6 minutes, an auto entry may take longer.
    if (!wanted_ && restPeriods_ != UINT32_MAX) ++restPeriods_;
    if (config_.autoEntryPeriods != 0 && !wanted_ && restPeriods_ >= config_.autoEntryPeriods) {
      wanted_ = true;  // from the next period on
      restPeriods_ = 0;
    }
    if (!view_.storage.on) return true;
    if (ticksLeft_ != 0) {
      --ticksLeft_;
      return false;
    }
    ticksLeft_ = static_cast<uint8_t>(config_.scanEvery - 1);
    return true;
  }

  // Monitor task, after each validated scan: current above the rest threshold leaves storage at once (the
  // next scan at the normal period) and starts the count to an automatic entry again.
  void scanned() {
    if (config_.scanEvery == 0 || atRest()) return;
    restPeriods_ = 0;
    if (wanted_) {
      wanted_ = false;
      set(false);
      ticksLeft_ = 0;
    }
  }

  SleepCommand sleep{};  // the monitor's (Bq769xDevice)

  bool on() const { return view_.storage.on; }
  bool wanted() const { return wanted_; }
  // The device's SLEEP as storage wants it now.
  bool deviceSleep() const { return view_.storage.on && config_.deviceSleep; }

 private:
  bool faulted() const { return status_.active != 0 || view_.deviceBlocks != 0; }
  bool atRest() const {
    const int32_t i = view_.currentMa;
    return !view_.hasCurrent || (i < 0 ? -i : i) <= config_.restCurrentMa;
  }
  void set(bool on) {
    StorageView& s = view_.storage;
    s.on = on;
    s.scanEvery = on ? config_.scanEvery : 0;
    s.period = config_.scanPeriod * (on ? config_.scanEvery : 1);
    s.deviceAge = on && config_.deviceSleep ? config_.deviceInterval : Duration{};
    // Stale after as many storage scan periods as normal ones, plus the device's own interval in SLEEP.
    s.staleExtra =
        on ? Duration{config_.staleAfter.us * (config_.scanEvery - 1) + s.deviceAge.us} : Duration{};
  }

  const StorageConfig& config_;
  PackView& view_;
  const PublishStatus& status_;
  bool wanted_ = false;
  uint8_t ticksLeft_ = 0;
  uint32_t restPeriods_ = 0;  // scan periods since the last scan that was not at rest (or since start-up)
};
#endif

// A build without storage (FW_STORAGE=0): every request unsupported, no state.
struct NoStorageMode {
  constexpr NoStorageMode(const StorageConfig&, PackView&, const PublishStatus&) {}
  static inline SleepCommand sleep{};  // named only behind kStorage: never used, nothing in RAM
  StorageRequest request(bool) { return StorageRequest::Unsupported; }
  bool tick() { return true; }
  void scanned() {}
  bool deviceSleep() const { return false; }
};

}  // namespace fw::app
