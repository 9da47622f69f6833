#include "app/command/slcan_adapter.hpp"
#include "app/publish/slcan.hpp"

namespace fw::app::command {

namespace {

constexpr uint8_t kCr = '\r', kBel = 0x07;
constexpr uint8_t kVersionAnswer[] = {'V',
                                      '0',
                                      '1',
                                      static_cast<uint8_t>('0' + kVersion.major % 10),
                                      static_cast<uint8_t>('0' + kVersion.minor % 10),
                                      kCr};

// The value of hex digit `c` (either case), or 16 if it is none.
uint32_t hexValue(uint32_t c) {
  const uint32_t lower = c | 0x20U;  // 'A'..'F' and 'a'..'f' alike
  if (c >= '0' && c <= '9') return c - '0';
  if (lower >= 'a' && lower <= 'f') return lower - 'a' + 10;
  return 16;
}

// A t or T line (its characters after the letter already hex digit values, execute()): identifier, DLC
// digit, exactly DLC data bytes. (Word-sized counters: Thumb masks a byte-sized one after every step.)
bool parseFrame(const uint8_t* line, uint32_t length, hal::CanFrame& f) {
  const bool extended = line[0] == 'T';
  const uint32_t idDigits = extended ? 8 : 3;
  if (length < 2 + idDigits) return false;
  uint32_t id = 0;
  for (uint32_t i = 1; i <= idDigits; ++i)
    id = id << 4 | line[i];
  const uint32_t dlc = line[1 + idDigits];
  if (dlc > 8 || id > (extended ? 0x1FFFFFFFU : 0x7FFU) || length != 2 + idDigits + 2 * dlc) return false;
  f.id = id;
  f.extended = extended;
  f.dlc = static_cast<uint8_t>(dlc);
  const uint8_t* digit = line + 2 + idDigits;
  for (uint32_t i = 0; i < 8; ++i, digit += 2)
    f.data[i] = i < dlc ? static_cast<uint8_t>(digit[0] << 4 | digit[1]) : 0;
  return true;
}

}  // namespace

bool SlcanAdapter::take(uint8_t byte) {
  if (byte == '\n') return false;
  if (byte == kCr) return true;
  if (state_.length < kMaxLine) {
    state_.line[state_.length++] = byte;
  } else {
    state_.overlong = true;
  }
  return false;
}

void SlcanAdapter::answer(const Info& info, Line& out) {
  out.answerLength = 1;
  out.hasFrame = false;
  if (state_.overlong || !execute(info, out)) out.answer[0] = kBel;  // a refusal leaves answerLength 1
  state_.length = 0;
  state_.overlong = false;
}

// False for a line to refuse (answer() answers BEL; a refusal changes neither answerLength nor hasFrame);
// otherwise out.answer holds the answer (CR unless set).
bool SlcanAdapter::execute(const Info& info, Line& out) {
  uint8_t* line = state_.line;
  const uint32_t n = state_.length;
  // Every valid line is a letter and hex digits alone (or nothing): the digits become their values here, once
  // for every command that has any.
  for (uint32_t i = 1; i < n; ++i) {
    const uint32_t v = hexValue(line[i]);
    if (v > 15) return false;
    line[i] = static_cast<uint8_t>(v);
  }
  uint8_t* a = out.answer;
  a[0] = kCr;
  if (n == 0) return true;
  const uint8_t c = line[0];
  if (c == 't' || c == 'T') {
    if (!state_.open || !parseFrame(line, n, out.frame)) return false;
    out.hasFrame = true;
    a[0] = c == 't' ? 'z' : 'Z', a[1] = kCr;
    out.answerLength = 2;
    return true;
  }
  if (c == 'S') {
    if (n != 2 || state_.open || line[1] > 8) return false;
    state_.bitrate = line[1];
    return true;
  }
  if (n != 1) return false;
  switch (c) {
    case 'O':
    case 'C':
      if (state_.open != (c == 'C')) return false;  // O only while closed, C only while open
      state_.open = c == 'O';
      return true;
    case 'V':
      for (uint8_t i = 0; i < sizeof kVersionAnswer; ++i)
        a[i] = kVersionAnswer[i];
      out.answerLength = sizeof kVersionAnswer;
      return true;
    case 'N':
      a[0] = 'N';
      for (uint8_t i = 0; i < 4; ++i)
        a[1 + i] = slcan::hexDigit(info.serial >> (12 - 4 * i));
      a[5] = kCr;
      out.answerLength = 6;
      return true;
    case 'F':
      if (!state_.open) return false;
      a[0] = 'F', a[1] = '0', a[2] = info.overrunSinceLast ? '8' : '0', a[3] = kCr;  // bit 3: data overrun
      out.answerLength = 4;
      return true;
    default:
      return false;
  }
}

}  // namespace fw::app::command
