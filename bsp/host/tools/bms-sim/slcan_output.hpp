// SlcanOutput: the SLCAN text an L1306 board sends on its back-channel UART, as `bms-sim --slcan` gives it.
//
//   --slcan FILE  the exact bytes the simulated UART carried (the SlcanPublisher's lines), written when the
//                 run ends.
//   --slcan pty   a pseudo-terminal in raw mode; its path goes to stderr. The run starts once a reader has
//                 opened it and sent SLCAN's open command O (python-can and slcand send C, S6, O once the
//                 port is set up; python-can after its sleep_after_open), or 3 s after it opened the terminal
//                 without one (a reader that is not an SLCAN tool), or after 60 s with no reader: the board
//                 is switched on once the PC is listening, so nothing piles up to arrive in one burst. Each
//                 write reaches the terminal once its last byte has left the simulated 115 200 Bd UART, and
//                 the run is paced to the wall clock, so the reader sees the board at its real rate. Apart
//                 from that O, what a reader sends is read and ignored: the board's firmware does not listen.
//                 At the end the run waits for the reader to take the rest and then to close the terminal
//                 (python-can's shutdown sends C and closes it), so a reader that stops after a silence ends
//                 cleanly instead of on a vanished port. Nothing waits without a bound: a reader that stops
//                 reading loses the oldest text beyond 64 KiB (counted on stderr, as a PC loses what a UART
//                 sends into a full buffer); the rest is waited for at most 5 s, the close at most 30 s more
//                 (2 s once the reader sent C).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace bmssim {

// What the board's SLCAN UART has sent so far: every byte in order, and when each write's last byte left the
// line (one entry per write, in microseconds of simulated time). The host board's SimSerial and the twin's
// UART model both give it.
struct SentText {
  const std::string& text;
  const std::vector<uint64_t>& writeEndsUs;
};

class SlcanOutput {
 public:
  // `target` is a file path or "pty". Returns null and sets `error` when it cannot be opened.
  static std::unique_ptr<SlcanOutput> open(const std::string& target, std::string& error);
  virtual ~SlcanOutput() = default;

  // After every simulated millisecond: what `uart` finished sending by `nowUs`.
  virtual void step(const SentText& uart, uint64_t nowUs) = 0;
  // At the end of the run; false (and `error`) when the text could not be written.
  virtual bool finish(const SentText& uart, std::string& error) = 0;
  // What the reader has sent since the last call (a file output: nothing).
  virtual std::string takeInput() { return {}; }
};

}  // namespace bmssim
