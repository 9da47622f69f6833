// Small simulated peripherals: serial port (the SLCAN back-channel, both directions), GPIO edge input and
// output, watchdog.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include <string_view>

#include "hal/gpio.hpp"
#include "hal/serial.hpp"
#include "hal/system.hpp"
#include "hal/watchdog.hpp"

namespace bsp::host {

class SimClock;
class SimIrq;

// 8N1 serial port. Transmit: a write occupies the line for 10 bit times per byte; the text is kept for
// inspection. Receive: what the PC sends (peerSend) arrives byte by byte at the same rate into a buffer of
// `rxDepth` bytes, as the L1306 BSP's UART receiver buffers it; each byte raises the receive interrupt, and a
// byte that finds the buffer full is lost (counted).
class SimSerial final : public fw::hal::SerialPort {
 public:
  SimSerial(SimClock& clock, SimIrq& irq, uint32_t baud = 115200, size_t rxDepth = 64);
  const std::string& text() const { return text_; }
  // When each write's last byte left the line, and where in text() it began (one entry per write()).
  const std::vector<uint64_t>& writeTimes() const { return writeTimes_; }
  const std::vector<size_t>& writeStarts() const { return writeStarts_; }
  bool busy() const { return busy_; }

  // The PC sends `bytes`: they arrive one after another, after whatever it sent before.
  void peerSend(std::string_view bytes);
  uint64_t received() const { return received_; }    // bytes that arrived (kept or lost)
  size_t backlog() const { return onLine_.size(); }  // sent by the PC, not arrived yet
  uint64_t byteTimeUs() const { return (10ULL * 1000000ULL + baud_ - 1) / baud_; }

 private:
  fw::Status doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) override;
  bool doRead(uint8_t& byte) override;
  void doOnReceive(const fw::hal::Notify& notify) override { rxNotify_ = notify; }
  uint32_t doLost() const override { return lost_; }
  void arrive();

  SimClock& clock_;
  SimIrq& irq_;
  uint32_t baud_;
  size_t rxDepth_;
  int line_;
  int rxLine_;
  fw::hal::Notify done_;
  fw::hal::Notify rxNotify_;
  bool busy_ = false;
  std::string text_;
  std::vector<uint64_t> writeTimes_;
  std::vector<size_t> writeStarts_;
  std::deque<uint8_t> onLine_;  // sent by the PC, not arrived yet
  std::deque<uint8_t> rx_;      // arrived, not read yet
  bool arriving_ = false;
  uint32_t lost_ = 0;
  uint64_t received_ = 0;
};

// An edge-interrupt input. drive(level) changes the pin; an edge of the configured polarity raises the IRQ.
class SimEdgeInput final : public fw::hal::EdgeInput {
 public:
  enum class Edge { Falling, Rising };
  SimEdgeInput(SimIrq& irq, std::string name, Edge edge, bool initialLevel);
  void drive(bool level);
  uint64_t edges() const { return edges_; }

 private:
  void doEnable(const fw::hal::Notify& notify) override { notify_ = notify; }
  void doDisable() override { notify_ = {}; }
  bool doLevel() const override { return level_; }
  SimIrq& irq_;
  int line_;
  Edge edge_;
  bool level_;
  uint64_t edges_ = 0;
  fw::hal::Notify notify_;
};

// An output pin that remembers every change with its time.
class SimDigitalOut final : public fw::hal::DigitalOut {
 public:
  explicit SimDigitalOut(const SimClock& clock, bool initial = false) : clock_(clock), level_(initial) {}
  const std::vector<std::pair<uint64_t, bool>>& history() const { return history_; }

 private:
  void doSet(bool high) override;
  bool doLevel() const override { return level_; }
  const SimClock& clock_;
  bool level_;
  std::vector<std::pair<uint64_t, bool>> history_;
};

// The MCU's identity (as a test sets it) and the restart into the bootloader: recorded, and the board goes on
// running (the twin models the real reset).
class SimSystem final : public fw::hal::SystemControl {
 public:
  explicit SimSystem(const SimClock& clock, fw::hal::ChipIdentity identity = {0x5A5A1306, 0, 0})
      : clock_(clock), identity_(identity) {}
  // When enterBootloader() was called, in us of simulated time (empty: never).
  const std::vector<uint64_t>& bootloaderEntries() const { return entries_; }

 private:
  fw::hal::ChipIdentity doIdentity() const override { return identity_; }
  void doEnterBootloader() override;
  const SimClock& clock_;
  fw::hal::ChipIdentity identity_;
  std::vector<uint64_t> entries_;
};

// A watchdog that records feed times and can tell whether a given timeout would have reset the MCU.
class SimWatchdog final : public fw::hal::Watchdog {
 public:
  explicit SimWatchdog(const SimClock& clock) : clock_(clock) {}
  const std::vector<uint64_t>& feeds() const { return feeds_; }
  // Longest time without a feed between `fromUs` and now.
  uint64_t longestGapUs(uint64_t fromUs) const;

 private:
  void doFeed() override;
  const SimClock& clock_;
  std::vector<uint64_t> feeds_;
};

}  // namespace bsp::host
