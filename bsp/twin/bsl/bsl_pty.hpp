// BslPty: the host's end of the chip's BSL UART as a pseudo-terminal (the XDS110 back-channel of a LaunchPad
// wired for the BSL), so `bmsctl flash --port /dev/pts/N` talks to the twin as to a board.
//
// - What a program writes to the terminal reaches the BSL's RX pin one byte per 10 bit times at the rate the
//   program set on the terminal (its termios output speed, read when the bytes are taken), on the twin's
//   timeline; a rate the BSL is not at loses the byte (RomBsl::receive). What the BSL sends is written to the
//   terminal if the program's rate matches the BSL's when the byte leaves, else lost.
// - The twin keeps the terminal's other side open itself, raw, so a program may open and close it any
//   number of times.
// - Fault injection (tests): dropHostByte(n) loses the n-th byte the host sends from then on.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "bsl/rom_bsl.hpp"
#include "machine.hpp"
#include "timeline.hpp"

namespace twin {

class BslPty {
 public:
  BslPty(Machine& machine, RomBsl& bsl);
  ~BslPty();
  BslPty(const BslPty&) = delete;
  BslPty& operator=(const BslPty&) = delete;

  bool open(std::string& error);
  const std::string& path() const { return path_; }
  int fd() const { return master_; }  // for poll()
  // Takes what the host wrote (without waiting) onto the line, and hands the host what the BSL sent.
  void service();
  // Waits up to `ms` milliseconds of wall time for the host to write.
  void waitForHost(int ms);
  // Host bytes still travelling to the BSL.
  bool inFlight() const { return !pending_.empty(); }

  void dropHostByte(uint64_t nth) { dropAt_ = nth == 0 ? 0 : received_ + nth; }
  uint64_t hostBytes() const { return received_; }
  uint64_t bslBytes() const { return sent_; }
  uint64_t lostToHost() const { return lostToHost_; }

 private:
  uint32_t hostBaud() const;
  void startNext();
  void deliver();

  Machine& machine_;
  RomBsl& bsl_;
  int master_ = -1, slave_ = -1;
  std::string path_;
  std::deque<std::pair<uint8_t, uint32_t>> pending_;  // byte, the rate it was sent at
  TimedEvent arrive_;
  std::vector<uint8_t> out_;
  uint64_t received_ = 0, sent_ = 0, lostToHost_ = 0, dropAt_ = 0;
};

}  // namespace twin
