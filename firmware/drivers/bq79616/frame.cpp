// BQ79616 frame codec (see frame.hpp). Frame layout: SLUSE81E §9.3.6.1.1 (command and response frames),
// CRC: §9.3.6.1.1.5 (CRC-16, polynomial 0x8005 reflected, init 0xFFFF, sent LSB first; a receiver runs the
// CRC over the whole frame and expects 0).
#include "drivers/bq79616/frame.hpp"

#include "core/bytes.hpp"
#include "core/crc.hpp"

namespace fw::drivers::bq79616 {

namespace {

// Writes INIT, the optional device id and the register; returns the header length.
size_t putHeader(uint8_t init, RequestType type, uint8_t device, uint16_t reg, uint8_t* out) {
  size_t n = 0;
  out[n++] = init;
  if (hasDeviceId(type)) out[n++] = device;
  bytes::storeBe16(out + n, reg);
  return n + 2;
}

size_t finish(uint8_t* out, size_t n) {
  bytes::storeLe16(out + n, crc::crc16(out, n));  // CRC low byte first
  return n + 2;
}

size_t commandSize(RequestType type, size_t dataBytes) {
  return 1 + (hasDeviceId(type) ? 1 : 0) + 2 + dataBytes + 2;
}

}  // namespace

size_t encodeWrite(RequestType type, uint8_t device, uint16_t reg, std::span<const uint8_t> data,
                   std::span<uint8_t> out) {
  if (isRead(type) || static_cast<uint8_t>(type) > 6) return 0;
  if (data.empty() || data.size() > kMaxWriteBytes) return 0;
  if (hasDeviceId(type) && device > kMaxAddress) return 0;
  if (out.size() < commandSize(type, data.size())) return 0;
  size_t n = putHeader(initByte(type, data.size()), type, device, reg, out.data());
  for (uint8_t b : data)
    out[n++] = b;
  return finish(out.data(), n);
}

size_t encodeRead(RequestType type, uint8_t device, uint16_t reg, size_t count, std::span<uint8_t> out) {
  if (!isRead(type)) return 0;
  if (count == 0 || count > kMaxReadBytes) return 0;
  if (hasDeviceId(type) && device > kMaxAddress) return 0;
  if (out.size() < commandSize(type, 1)) return 0;
  size_t n = putHeader(initByte(type, 0), type, device, reg, out.data());
  out[n++] = static_cast<uint8_t>(count - 1);
  return finish(out.data(), n);
}

Status parseResponse(std::span<const uint8_t> bytes, uint16_t reg, size_t count, ResponseFrame& out) {
  const size_t size = responseSize(count);
  if (bytes.size() < size) return Status::Truncated;
  if (crc::crc16(bytes.data(), size) != 0) {
    // Tell a corrupted frame from an intact frame of another length: only the latter checks under its own
    // length byte. Either way nothing of it is used.
    const size_t own = responseSize(static_cast<size_t>(bytes[0]) + 1);
    if (own != size && own <= bytes.size() && crc::crc16(bytes.data(), own) == 0) return Status::Length;
    return Status::Crc;
  }
  if (static_cast<size_t>(bytes[0]) + 1 != count) return Status::Length;
  // DEV_ID bits 7:6 are reserved and always 0 (SLUSE81E §9.3.6.1.1.2).
  if (bytes[1] > kMaxAddress || bytes::loadBe16(bytes.data() + 2) != reg) return Status::DeviceId;
  out.device = bytes[1];
  out.reg = reg;
  out.data = bytes.subspan(4, count);
  return Status::Ok;
}

}  // namespace fw::drivers::bq79616
