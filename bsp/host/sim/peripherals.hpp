// Small simulated peripherals: serial transmitter (SLCAN back-channel), GPIO edge input and output, watchdog.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hal/gpio.hpp"
#include "hal/serial.hpp"
#include "hal/watchdog.hpp"

namespace bsp::host {

class SimClock;
class SimIrq;

// 8N1 transmitter: a write occupies the line for 10 bit times per byte; the text is kept for inspection.
class SimSerialTx final : public fw::hal::SerialTx {
 public:
  SimSerialTx(SimClock& clock, SimIrq& irq, uint32_t baud = 115200);
  const std::string& text() const { return text_; }
  // When each write's last byte left the line (one entry per write()).
  const std::vector<uint64_t>& writeTimes() const { return writeTimes_; }
  void clear() { text_.clear(); }
  bool busy() const { return busy_; }

 private:
  fw::Status doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) override;
  SimClock& clock_;
  SimIrq& irq_;
  uint32_t baud_;
  int line_;
  fw::hal::Notify done_;
  bool busy_ = false;
  std::string text_;
  std::vector<uint64_t> writeTimes_;
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
