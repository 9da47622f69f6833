// Field-by-field little-endian encoding of the stored records (layout: records.hpp, README.md).
#include "app/store/records.hpp"

#include "core/bytes.hpp"

namespace fw::app::store {
using namespace fw::bytes;

void encode(const SettingsRecord& r, std::span<uint8_t, SettingsRecord::kBytes> out) {
  for (uint32_t i = 0; i < r.value.size(); ++i)
    storeLe32(out.data() + 4 * i, static_cast<uint32_t>(r.value[i]));
}
bool decode(std::span<const uint8_t> in, SettingsRecord& r) {
  if (in.size() != SettingsRecord::kBytes) return false;
  for (uint32_t i = 0; i < r.value.size(); ++i)
    r.value[i] = loadLeI32(in.data() + 4 * i);
  return true;
}

void encode(const ProtectionLogRecord::Entry& e, std::span<uint8_t, ProtectionLogRecord::kEntryBytes> out) {
  out[0] = e.rule;
  out[1] = out[2] = out[3] = 0;
  storeLe32(out.data() + 4, e.uptimeS);
  storeLe32(out.data() + 8, static_cast<uint32_t>(e.value));
}
void encode(const ProtectionLogRecord& r, std::span<uint8_t, ProtectionLogRecord::kBytes> out) {
  out[0] = r.count;
  out[1] = out[2] = out[3] = 0;
  for (uint32_t i = 0; i < r.entry.size(); ++i)
    encode(r.entry[i],
           std::span<uint8_t, ProtectionLogRecord::kEntryBytes>(
               out.data() + ProtectionLogRecord::entryOffset(i), ProtectionLogRecord::kEntryBytes));
}
bool decode(std::span<const uint8_t> in, ProtectionLogRecord& r) {
  if (in.size() != ProtectionLogRecord::kBytes || in[0] > ProtectionLogRecord::kEntries) return false;
  r.count = in[0];
  for (uint32_t i = 0; i < r.entry.size(); ++i) {
    const uint8_t* p = in.data() + ProtectionLogRecord::entryOffset(i);
    r.entry[i] = ProtectionLogRecord::Entry{p[0], loadLe32(p + 4), loadLeI32(p + 8)};
  }
  return true;
}

void encode(const FaultRecord& r, std::span<uint8_t, FaultRecord::kBytes> out) {
  out[0] = r.resetCause;
  out[1] = r.module;
  storeLe16(out.data() + 2, r.code);
  storeLe32(out.data() + 4, r.pc);
  storeLe32(out.data() + 8, r.uptimeS);
}
bool decode(std::span<const uint8_t> in, FaultRecord& r) {
  if (in.size() != FaultRecord::kBytes) return false;
  r = FaultRecord{in[0], loadLe16(in.data() + 2), loadLe32(in.data() + 4), loadLe32(in.data() + 8), in[1]};
  return true;
}

void encode(const SocRecord& r, std::span<uint8_t, SocRecord::kBytes> out) {
  storeLe16(out.data(), r.permille);
  out[2] = out[3] = 0;
  storeLe32(out.data() + 4, r.remainingMah);
}
bool decode(std::span<const uint8_t> in, SocRecord& r) {
  if (in.size() != SocRecord::kBytes) return false;
  r = SocRecord{loadLe16(in.data()), loadLe32(in.data() + 4)};
  return true;
}

}  // namespace fw::app::store
