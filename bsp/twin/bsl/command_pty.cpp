#include "bsl/command_pty.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include "bsl/raw_pty.hpp"

namespace twin {

namespace {

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// "tiiildd.." (standard identifier, Lawicel CAN232) into a frame; false when malformed.
bool parseFrame(const std::string& line, fw::hal::CanFrame& f) {
  if (line.size() < 5 || line[0] != 't') return false;
  uint32_t id = 0;
  for (size_t i = 1; i < 4; ++i) {
    const int d = hexDigit(line[i]);
    if (d < 0) return false;
    id = id << 4 | static_cast<uint32_t>(d);
  }
  const int dlc = hexDigit(line[4]);
  if (id > 0x7FF || dlc < 0 || dlc > 8 || line.size() != 5 + 2 * static_cast<size_t>(dlc)) return false;
  f = {};
  f.id = id;
  f.dlc = static_cast<uint8_t>(dlc);
  for (int i = 0; i < dlc; ++i) {
    const int hi = hexDigit(line[5 + 2 * i]), lo = hexDigit(line[6 + 2 * i]);
    if (hi < 0 || lo < 0) return false;
    f.data[static_cast<size_t>(i)] = static_cast<uint8_t>(hi << 4 | lo);
  }
  return true;
}

std::string frameLine(const fw::hal::CanFrame& f) {
  char buf[32];
  int n = f.extended ? std::snprintf(buf, sizeof buf, "T%08X%u", f.id, f.dlc)
                     : std::snprintf(buf, sizeof buf, "t%03X%u", f.id, f.dlc);
  std::string line(buf, static_cast<size_t>(n));
  for (uint8_t i = 0; i < f.dlc && i < 8; ++i) {
    n = std::snprintf(buf, sizeof buf, "%02X", f.data[i]);
    line.append(buf, static_cast<size_t>(n));
  }
  return line + "\r";
}

}  // namespace

CommandPty::~CommandPty() {
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

bool CommandPty::open(std::string& error) {
  return openRawPty(B115200, master_, slave_, path_, error);
}

void CommandPty::toHost(const std::string& text) {
  out_ += text;
}

void CommandPty::adapterLine(const std::string& line) {
  if (line.empty()) {
    toHost("\r");
    return;
  }
  fw::hal::CanFrame f;
  switch (line[0]) {
    case 'O':
    case 'C':
      if (line.size() != 1) break;
      open_ = line[0] == 'O';
      toHost("\r");
      return;
    case 'S':
      if (line.size() != 2 || line[1] < '0' || line[1] > '8') break;
      toHost("\r");
      return;
    case 'F':
      if (line.size() != 1) break;
      toHost("F00\r");  // no error flags
      return;
    case 'V':
      if (line.size() != 1) break;
      toHost("V1010\r");
      return;
    case 'N':
      if (line.size() != 1) break;
      toHost("NTWIN\r");
      return;
    case 't':
      if (!open_ || !parseFrame(line, f)) break;
      board_.sendCan(f);
      toHost("z\r");
      return;
    default:
      break;
  }
  toHost("\a");
}

void CommandPty::service() {
  char buf[512];
  for (;;) {
    const ssize_t n = ::read(master_, buf, sizeof buf);
    if (n <= 0) break;
    if (board_.image().part == Part::L1306) {
      board_.sendSerial(std::string_view(buf, static_cast<size_t>(n)));
      continue;
    }
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] == '\r') {
        adapterLine(line_);
        line_.clear();
      } else if (line_.size() < 64) {
        line_ += buf[i];
      }
    }
  }
  const auto& lines = board_.slcanLines();
  for (; linesSent_ < lines.size(); ++linesSent_)
    toHost(lines[linesSent_].text);
  const auto& frames = board_.canFrames();
  for (; framesSent_ < frames.size(); ++framesSent_) {
    if (open_) toHost(frameLine(frames[framesSent_].frame));
  }
  size_t done = 0;
  while (done < out_.size()) {
    const ssize_t n = ::write(master_, out_.data() + done, out_.size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  out_.erase(0, done);
  if (out_.size() > 65536) out_.erase(0, out_.size() - 65536);  // nobody reads: keep the newest
}

}  // namespace twin
