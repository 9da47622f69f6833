#include "app/publish/slcan.hpp"

namespace fw::app::slcan {

namespace {

// A line is one run of hex digits, written from its last digit back: each value is shifted out four bits
// at a time. Writes the `n` digits of `value` that end just before `end` and returns where they start. Both
// encoders share it.
uint8_t* digits(uint8_t* end, uint32_t value, size_t n) {
  for (; n != 0; --n, value >>= 4) {
    const auto d = static_cast<uint8_t>(value & 0xFU);
    *--end = static_cast<uint8_t>(d < 10 ? '0' + d : 'A' - 10 + d);
  }
  return end;
}

}  // namespace

size_t encode(const hal::CanFrame& frame, std::span<uint8_t> out) {
  const bool extended = frame.extended;
  if (frame.dlc > 8 || frame.id > (extended ? 0x1FFFFFFFU : 0x7FFU)) return 0;
  const size_t idDigits = extended ? 8 : 3;
  const size_t length = idDigits + 3 + 2U * frame.dlc;  // letter, id, DLC digit, data, CR
  if (out.size() < length) return 0;
  // The data bytes low nibble first, then the DLC, then the identifier.
  uint8_t* p = out.data() + length - 1;
  *p = '\r';
  for (size_t i = frame.dlc; i != 0; --i)
    p = digits(p, frame.data[i - 1], 2);
  p = digits(p, frame.dlc, 1);
  p = digits(p, frame.id, idDigits);
  *--p = extended ? 'T' : 't';
  return length;
}

void encodeStandard(uint16_t id, const std::array<uint8_t, 8>& data, uint8_t* out) {
  // Front to back: 't', the identifier and the DLC digit as four digits of (id << 4 | 8), then each data
  // byte's two digits.
  uint8_t* p = out;
  *p++ = 't';
  uint32_t w = static_cast<uint32_t>(id) << 20 | 8U << 16;  // the four digits at the top of a 32-bit word
  for (size_t i = 0; i < 4 + 2 * data.size(); ++i) {
    if (i >= 4 && (i & 1) == 0) w = static_cast<uint32_t>(data[(i - 4) / 2]) << 24;  // next byte's digits
    const auto d = static_cast<uint8_t>(w >> 28);
    *p++ = static_cast<uint8_t>(d < 10 ? '0' + d : 'A' - 10 + d);
    w <<= 4;
  }
  *p = '\r';
}

}  // namespace fw::app::slcan
