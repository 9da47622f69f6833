#include "app/slcan.hpp"

namespace fw::app::slcan {

size_t encode(const hal::CanFrame& frame, std::span<uint8_t> out) {
  const bool extended = frame.extended;
  if (frame.dlc > 8 || frame.id > (extended ? 0x1FFFFFFFU : 0x7FFU)) return 0;
  const size_t idDigits = extended ? 8 : 3;
  const size_t length = idDigits + 3 + 2U * frame.dlc;  // letter, id, DLC digit, data, CR
  if (out.size() < length) return 0;
  // The whole line is one run of hex digits, written from its last digit back: the data bytes low nibble
  // first, then the DLC, then the identifier, each shifted out four bits at a time.
  uint8_t* p = out.data() + length - 1;
  *p = '\r';
  auto digits = [&p](uint32_t value, size_t n) {
    for (; n != 0; --n, value >>= 4) {
      const auto d = static_cast<uint8_t>(value & 0xFU);
      *--p = static_cast<uint8_t>(d < 10 ? '0' + d : 'A' - 10 + d);
    }
  };
  for (size_t i = frame.dlc; i != 0; --i)
    digits(frame.data[i - 1], 2);
  digits(frame.dlc, 1);
  digits(frame.id, idDigits);
  *--p = extended ? 'T' : 't';
  return length;
}

}  // namespace fw::app::slcan
