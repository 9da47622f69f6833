// What the board published about pack storage (bms.yaml StorageStatus,
// firmware/app/monitors/storage_mode.hpp), read back from its frames as a receiver sees them: bms-sim
// --json's storage_* and measurement_age_* keys.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "image_sim.hpp"

namespace bmssim {

struct StorageSummary {
  bool sent = false;                  // the image sent StorageStatus at all
  bool on = false;                    // the last one: in storage
  uint32_t scanPeriodMs = 0;          // ... its ScanPeriod
  std::optional<uint32_t> ageMs;      // ... its MeasurementAge (nullopt: not available)
  std::optional<uint64_t> enteredUs;  // the first frame in storage
  std::optional<uint64_t> leftUs;     // the first frame in normal mode after that
  uint32_t maxAgeMs = 0;              // the largest MeasurementAge published
};

StorageSummary storageSummary(const std::vector<SentFrame>& frames);

}  // namespace bmssim
