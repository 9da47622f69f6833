// SerialPort: a POSIX serial port (termios only, no library) set up the way the MSPM0 ROM bootloader needs
// it: raw 8N1, no flow control (SLAU887 4.2.2.1: "8 data bits, no parity, 1 stop bit", no handshake), the
// receiver on, modem lines ignored.
//
// Contract
// - open(): O_RDWR | O_NOCTTY | O_NONBLOCK, then an exclusive advisory lock (flock) and TIOCEXCL, so a
//   second bmsctl (or anything that honours them) gets "busy" instead of sharing the line; both are released
//   by the destructor. The failure says which: the path does not exist, is not a terminal, is in use, or may
//   not be opened (permission: the user is not in the port's group, usually `dialout`).
// - setBaud(): any rate the BSL knows (4800 .. 3 000 000) that the platform's termios has a constant for.
// - read(): waits with poll() until `count` bytes arrived or the deadline passed; returns what came.
// - All waits are bounded by the caller's deadline; nothing blocks forever.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace bmsctl::flash {

using Clock = std::chrono::steady_clock;

class SerialPort {
 public:
  enum class OpenError : uint8_t { None, Missing, NotATerminal, Busy, Permission, Other };

  static std::unique_ptr<SerialPort> open(const std::string& path, OpenError& error, std::string& detail);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  const std::string& path() const { return path_; }
  bool setBaud(uint32_t baud);
  uint32_t baud() const { return baud_; }
  bool write(std::span<const uint8_t> bytes);
  std::vector<uint8_t> read(size_t count, Clock::time_point deadline);
  // Discards what arrived and is not read yet.
  void flushInput();
  // Waits until the bytes written have left (bounded by the platform; a USB CDC port returns early).
  void drainOutput();
  // Microseconds one byte takes on the line at the current rate (10 bits: start, 8 data, stop).
  uint64_t byteMicros() const { return 10000000ULL / baud_; }

 private:
  SerialPort(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_;
  std::string path_;
  uint32_t baud_ = 9600;
};

}  // namespace bmsctl::flash
