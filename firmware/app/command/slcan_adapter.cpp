#include "app/command/slcan_adapter.hpp"

namespace fw::app::command {

namespace {

constexpr uint8_t kCr = '\r', kBel = 0x07;

int hexValue(uint8_t c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// `n` hex digits from `p` into `out`; false if any is not a hex digit.
bool hexAt(const uint8_t* p, uint8_t n, uint32_t& out) {
  out = 0;
  for (uint8_t i = 0; i < n; ++i) {
    const int v = hexValue(p[i]);
    if (v < 0) return false;
    out = out << 4 | static_cast<uint32_t>(v);
  }
  return true;
}

uint8_t hexDigit(uint32_t v) {
  v &= 0xFU;
  return static_cast<uint8_t>(v < 10 ? '0' + v : 'A' - 10 + v);
}

// A t or T line: identifier, DLC digit, exactly DLC data bytes.
bool parseFrame(const uint8_t* line, uint8_t length, hal::CanFrame& f) {
  const bool extended = line[0] == 'T';
  const uint8_t idDigits = extended ? 8 : 3;
  uint32_t id = 0, dlc = 0;
  if (length < 2 + idDigits || !hexAt(line + 1, idDigits, id) || !hexAt(line + 1 + idDigits, 1, dlc))
    return false;
  if (dlc > 8 || id > (extended ? 0x1FFFFFFFU : 0x7FFU) || length != 2 + idDigits + 2 * dlc) return false;
  f = hal::CanFrame{id, extended, static_cast<uint8_t>(dlc), {}};
  for (uint8_t i = 0; i < dlc; ++i) {
    uint32_t b = 0;
    if (!hexAt(line + 2 + idDigits + 2 * i, 2, b)) return false;
    f.data[i] = static_cast<uint8_t>(b);
  }
  return true;
}

}  // namespace

bool SlcanAdapter::feed(uint8_t byte, const Info& info, Line& out) {
  if (byte == '\n') return false;
  if (byte != kCr) {
    if (state_.length < kMaxLine) {
      state_.line[state_.length++] = byte;
    } else {
      state_.overlong = true;
    }
    return false;
  }
  out.answerLength = 0;
  out.hasFrame = false;
  if (!state_.overlong) execute(info, out);
  if (out.answerLength == 0) {  // refused
    out.answer[0] = kBel;
    out.answerLength = 1;
  }
  state_.length = 0;
  state_.overlong = false;
  return true;
}

// Leaves out.answerLength 0 for a line to refuse (feed() answers BEL).
void SlcanAdapter::execute(const Info& info, Line& out) {
  const uint8_t* line = state_.line;
  const uint8_t n = state_.length;
  uint8_t* a = out.answer;
  auto ok = [&] {
    a[0] = kCr;
    out.answerLength = 1;
  };
  if (n == 0) return ok();
  switch (line[0]) {
    case 'O':
      if (n == 1 && !state_.open) state_.open = true, ok();
      return;
    case 'C':
      if (n == 1 && state_.open) state_.open = false, ok();
      return;
    case 'S':
      if (n == 2 && !state_.open && line[1] >= '0' && line[1] <= '8') state_.bitrate = line[1] - '0', ok();
      return;
    case 'V':
      if (n != 1) return;
      a[0] = 'V', a[1] = '0', a[2] = '1';
      a[3] = static_cast<uint8_t>('0' + info.version / 10 % 10),
      a[4] = static_cast<uint8_t>('0' + info.version % 10);
      a[5] = kCr;
      out.answerLength = 6;
      return;
    case 'N':
      if (n != 1) return;
      a[0] = 'N';
      for (uint8_t i = 0; i < 4; ++i)
        a[1 + i] = hexDigit(info.serial >> (12 - 4 * i));
      a[5] = kCr;
      out.answerLength = 6;
      return;
    case 'F': {
      if (n != 1 || !state_.open) return;
      const uint8_t flags = info.overrunSinceLast ? 0x08 : 0x00;
      a[0] = 'F', a[1] = hexDigit(flags >> 4), a[2] = hexDigit(flags), a[3] = kCr;
      out.answerLength = 4;
      return;
    }
    case 't':
    case 'T':
      if (!state_.open || !parseFrame(line, n, out.frame)) return;
      out.hasFrame = true;
      a[0] = line[0] == 't' ? 'z' : 'Z', a[1] = kCr;
      out.answerLength = 2;
      return;
    default:
      return;
  }
}

}  // namespace fw::app::command
