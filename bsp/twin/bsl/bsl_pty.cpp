#include "bsl/bsl_pty.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include "bsl/raw_pty.hpp"

namespace twin {

namespace {

uint32_t rate(speed_t speed) {
  switch (speed) {
    case B4800:
      return 4800;
    case B9600:
      return 9600;
    case B19200:
      return 19200;
    case B38400:
      return 38400;
    case B57600:
      return 57600;
    case B115200:
      return 115200;
#ifdef B1000000
    case B1000000:
      return 1000000;
#endif
#ifdef B2000000
    case B2000000:
      return 2000000;
#endif
#ifdef B3000000
    case B3000000:
      return 3000000;
#endif
    default:
      return 0;
  }
}

}  // namespace

BslPty::BslPty(Machine& machine, RomBsl& bsl)
    : machine_(machine), bsl_(bsl), arrive_(machine.timeline(), [this] { deliver(); }) {
  bsl_.onTransmit([this](uint8_t byte, uint32_t baud) {
    if (hostBaud() == baud) {
      out_.push_back(byte);
      ++sent_;
    } else {
      ++lostToHost_;
    }
  });
}

BslPty::~BslPty() {
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

bool BslPty::open(std::string& error) {
  // The ROM bootloader starts at 9600 Bd (SLAU887).
  return openRawPty(B9600, master_, slave_, path_, error);
}

uint32_t BslPty::hostBaud() const {
  termios tio{};
  if (slave_ < 0 || tcgetattr(slave_, &tio) != 0) return 0;
  return rate(cfgetospeed(&tio));
}

void BslPty::service() {
  uint8_t buf[4096];
  for (;;) {
    const ssize_t n = ::read(master_, buf, sizeof buf);
    if (n <= 0) break;
    const uint32_t baud = hostBaud();
    for (ssize_t i = 0; i < n; ++i)
      pending_.emplace_back(buf[i], baud);
    startNext();
  }
  size_t done = 0;
  while (done < out_.size()) {
    const ssize_t n = ::write(master_, out_.data() + done, out_.size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  out_.erase(out_.begin(), out_.begin() + static_cast<long>(done));
}

void BslPty::startNext() {
  if (pending_.empty() || arrive_.armed()) return;
  const uint32_t baud = pending_.front().second != 0 ? pending_.front().second : 9600;
  arrive_.after(10ULL * machine_.clockHz() / baud);
}

void BslPty::deliver() {
  const auto [byte, baud] = pending_.front();
  pending_.pop_front();
  if (++received_ != dropAt_) bsl_.receive(byte, baud);
  startNext();
}

void BslPty::waitForHost(int ms) {
  pollfd p{master_, POLLIN, 0};
  poll(&p, 1, ms);
}

}  // namespace twin
