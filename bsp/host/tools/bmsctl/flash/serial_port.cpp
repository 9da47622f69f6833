#include "flash/serial_port.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

namespace bmsctl::flash {

namespace {

speed_t speedConstant(uint32_t baud) {
  switch (baud) {
    case 4800:
      return B4800;
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
#ifdef B1000000
    case 1000000:
      return B1000000;
#endif
#ifdef B2000000
    case 2000000:
      return B2000000;
#endif
#ifdef B3000000
    case 3000000:
      return B3000000;
#endif
    default:
      return B0;
  }
}

}  // namespace

std::unique_ptr<SerialPort> SerialPort::open(const std::string& path, OpenError& error, std::string& detail) {
  error = OpenError::None;
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    detail = std::strerror(e);
    error = e == ENOENT || e == ENODEV || e == ENXIO ? OpenError::Missing
            : e == EBUSY                             ? OpenError::Busy
            : e == EACCES || e == EPERM              ? OpenError::Permission
                                                     : OpenError::Other;
    return nullptr;
  }
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) {
    detail = std::strerror(errno);
    error = OpenError::NotATerminal;
    ::close(fd);
    return nullptr;
  }
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    detail = "another program holds its lock";
    error = OpenError::Busy;
    ::close(fd);
    return nullptr;
  }
  ioctl(fd, TIOCEXCL);
  cfmakeraw(&tio);
  tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS | CSIZE);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, B9600);
  cfsetospeed(&tio, B9600);
  if (tcsetattr(fd, TCSANOW, &tio) != 0) {
    detail = std::strerror(errno);
    error = OpenError::Other;
    ::close(fd);
    return nullptr;
  }
  tcflush(fd, TCIOFLUSH);
  return std::unique_ptr<SerialPort>(new SerialPort(fd, path));
}

SerialPort::~SerialPort() {
  ioctl(fd_, TIOCNXCL);
  flock(fd_, LOCK_UN);
  ::close(fd_);
}

bool SerialPort::setBaud(uint32_t baud) {
  const speed_t speed = speedConstant(baud);
  termios tio{};
  if (speed == B0 || tcgetattr(fd_, &tio) != 0) return false;
  cfsetispeed(&tio, speed);
  cfsetospeed(&tio, speed);
  if (tcsetattr(fd_, TCSANOW, &tio) != 0) return false;
  baud_ = baud;
  return true;
}

bool SerialPort::write(std::span<const uint8_t> bytes) {
  size_t done = 0;
  const auto deadline =
      Clock::now() + std::chrono::microseconds(byteMicros() * bytes.size()) + std::chrono::seconds(2);
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd p{fd_, POLLOUT, 0};
    poll(&p, 1, static_cast<int>(left));
  }
  return true;
}

std::vector<uint8_t> SerialPort::read(size_t count, Clock::time_point deadline) {
  std::vector<uint8_t> out;
  uint8_t buf[512];
  while (out.size() < count) {
    const ssize_t n = ::read(fd_, buf, std::min(sizeof buf, count - out.size()));
    if (n > 0) {
      out.insert(out.end(), buf, buf + n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) break;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) break;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000))) > 0 &&
        (p.revents & (POLLHUP | POLLERR)))
      break;  // the other end is gone (a pty whose master closed): nothing more will come
  }
  return out;
}

void SerialPort::flushInput() {
  tcflush(fd_, TCIFLUSH);
}

void SerialPort::drainOutput() {
  tcdrain(fd_);
}

}  // namespace bmsctl::flash
