// StorageConfig: a pack's storage mode (storage_mode.hpp), as its pack file's `storage` gives it
// (regmapgen pack generates fw::pack::kStorage).
#pragma once

#include <cstdint>

#include "core/time.hpp"

namespace fw::app {

struct StorageConfig {
  uint8_t scanEvery = 0;          // scan periods per scan in storage; 0: this pack has no storage mode
  bool deviceSleep = false;       // the device may SLEEP in storage (BQ769x2, BQ7690x)
  uint32_t autoEntryPeriods = 0;  // scan periods at rest before storage begins on its own; 0: command only
  int32_t restCurrentMa = 0;      // |current| at or below it is at rest (the pack's rest threshold)
  Duration deviceInterval{};      // the device's own measurement interval in its SLEEP (Voltage Time)
  Duration staleAfter{};          // the limits' staleAfter at the normal scan period
  Duration scanPeriod{};          // the normal scan period
};

// What a build without storage (FW_STORAGE=0) keeps of it: nothing.
struct NoStorageConfig {
  constexpr NoStorageConfig() = default;
  constexpr NoStorageConfig(const StorageConfig&) {}
  static constexpr StorageConfig kNone{};
  constexpr operator const StorageConfig&() const { return kNone; }
};

}  // namespace fw::app
