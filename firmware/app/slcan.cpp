#include "app/slcan.hpp"

namespace fw::app::slcan {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";

void putHex(uint8_t*& p, uint32_t value, int digits) {
  for (int i = digits - 1; i >= 0; --i)
    *p++ = static_cast<uint8_t>(kHex[(value >> (4 * i)) & 0xFU]);
}

}  // namespace

size_t encode(const hal::CanFrame& frame, std::span<uint8_t> out) {
  if (frame.dlc > 8) return 0;
  if (frame.extended ? frame.id > 0x1FFFFFFFU : frame.id > 0x7FFU) return 0;
  const size_t length = 1 + (frame.extended ? 8 : 3) + 1 + 2U * frame.dlc + 1;
  if (out.size() < length) return 0;
  uint8_t* p = out.data();
  *p++ = frame.extended ? 'T' : 't';
  putHex(p, frame.id, frame.extended ? 8 : 3);
  putHex(p, frame.dlc, 1);
  for (uint8_t i = 0; i < frame.dlc; ++i)
    putHex(p, frame.data[i], 2);
  *p++ = '\r';
  return length;
}

}  // namespace fw::app::slcan
