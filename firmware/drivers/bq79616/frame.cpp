// BQ79616 frame codec (see frame.hpp). Frame layout: SLUSE81E §9.3.6.1.1 (command and response frames),
// CRC: §9.3.6.1.1.5 (CRC-16, polynomial 0x8005 reflected, init 0xFFFF, sent LSB first; a receiver runs the
// CRC over the whole frame and expects 0).
//
// The checked entry points (encodeWrite/encodeRead/parseResponse) validate and then call the unchecked cores
// (encodeFrame/checkResponse), which the chain driver calls directly for its own, valid by construction,
// frames: the firmware image then carries one copy of the frame layout and none of the argument checks.
#include "drivers/bq79616/frame.hpp"

#include "core/bytes.hpp"
#include "core/crc.hpp"

namespace fw::drivers::bq79616 {

namespace {

// The checks encodeWrite() and encodeRead() share: a device id a single-device frame can carry, and room for
// the frame in `out`.
bool fits(RequestType type, uint8_t device, size_t dataBytes, std::span<uint8_t> out) {
  if (hasDeviceId(type) && device > kMaxAddress) return false;
  return out.size() >= 1 + (hasDeviceId(type) ? 1U : 0U) + 2 + dataBytes + 2;
}

}  // namespace

size_t encodeFrame(uint8_t init, uint8_t device, uint16_t reg, const uint8_t* data, size_t n, uint8_t* out) {
  uint8_t* p = out;
  *p++ = init;
  // Only the single-device types (0 and 1: INIT bits 6:5 clear) carry a device id.
  if ((init & 0x60U) == 0) *p++ = device;
  bytes::storeBe16(p, reg);
  p += 2;
  for (size_t i = 0; i < n; ++i)
    *p++ = data[i];
  const auto len = static_cast<size_t>(p - out);
  bytes::storeLe16(p, crc::crc16(out, len));  // CRC low byte first
  return len + 2;
}

size_t encodeWrite(RequestType type, uint8_t device, uint16_t reg, std::span<const uint8_t> data,
                   std::span<uint8_t> out) {
  if (isRead(type) || static_cast<uint8_t>(type) > 6) return 0;
  if (data.empty() || data.size() > kMaxWriteBytes) return 0;
  if (!fits(type, device, data.size(), out)) return 0;
  return encodeFrame(initByte(type, data.size()), device, reg, data.data(), data.size(), out.data());
}

size_t encodeRead(RequestType type, uint8_t device, uint16_t reg, size_t count, std::span<uint8_t> out) {
  if (!isRead(type)) return 0;
  if (count == 0 || count > kMaxReadBytes) return 0;
  if (!fits(type, device, 1, out)) return 0;
  const auto last = static_cast<uint8_t>(count - 1);
  return encodeFrame(initByte(type, 0), device, reg, &last, 1, out.data());
}

Status checkResponse(const uint8_t* frame, size_t available, uint16_t reg, size_t count) {
  const size_t size = responseSize(count);
  if (available < size) return Status::Truncated;
  if (crc::crc16(frame, size) != 0) {
    // Tell a corrupted frame from an intact frame of another length: only the latter checks under its own
    // length byte. Either way nothing of it is used.
    const size_t own = responseSize(static_cast<size_t>(frame[0]) + 1);
    if (own != size && own <= available && crc::crc16(frame, own) == 0) return Status::Length;
    return Status::Crc;
  }
  if (static_cast<size_t>(frame[0]) + 1 != count) return Status::Length;
  // DEV_ID bits 7:6 are reserved and always 0 (SLUSE81E §9.3.6.1.1.2).
  if (frame[1] > kMaxAddress || bytes::loadBe16(frame + 2) != reg) return Status::DeviceId;
  return Status::Ok;
}

Status parseResponse(std::span<const uint8_t> bytes, uint16_t reg, size_t count, ResponseFrame& out) {
  const Status s = checkResponse(bytes.data(), bytes.size(), reg, count);
  if (s != Status::Ok) return s;
  out.device = bytes[1];
  out.reg = reg;
  out.data = bytes.subspan(4, count);
  return Status::Ok;
}

}  // namespace fw::drivers::bq79616
