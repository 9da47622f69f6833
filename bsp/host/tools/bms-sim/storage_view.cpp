#include "storage_view.hpp"

#include "can/bms.hpp"

namespace bmssim {

namespace bms = fw::can::bms;

StorageSummary storageSummary(const std::vector<SentFrame>& frames) {
  StorageSummary s;
  for (const SentFrame& f : frames) {
    if (f.id != bms::StorageStatus::kId || f.extended || f.data.size() != 8) continue;
    fw::hal::CanFrame c{f.id, false, 8, {}};
    for (size_t i = 0; i < 8; ++i)
      c.data[i] = f.data[i];
    const auto g = bms::StorageStatus::unpack(c);
    s.sent = true;
    s.on = g.mode == 1;
    s.scanPeriodMs = g.scanPeriod;
    const bool known = g.measurementAge != bms::StorageStatus::kMeasurementAgeNotAvailable;
    s.ageMs = known ? std::optional<uint32_t>(g.measurementAge) : std::nullopt;
    if (known && g.measurementAge > s.maxAgeMs) s.maxAgeMs = g.measurementAge;
    if (s.on && !s.enteredUs) s.enteredUs = f.timeUs;
    if (!s.on && s.enteredUs && !s.leftUs) s.leftUs = f.timeUs;
  }
  return s;
}

}  // namespace bmssim
