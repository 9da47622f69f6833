#include "sim/peripherals.hpp"

#include <algorithm>

#include "sim/sim_clock.hpp"
#include "sim/sim_irq.hpp"

namespace bsp::host {

SimSerial::SimSerial(SimClock& clock, SimIrq& irq, uint32_t baud, size_t rxDepth)
    : clock_(clock),
      irq_(irq),
      baud_(baud),
      rxDepth_(rxDepth),
      line_(irq.attach("serial",
                       [this] {
                         busy_ = false;
                         fw::hal::Notify done = done_;
                         done_ = {};
                         done();
                       })),
      rxLine_(irq.attach("serial-rx", [this] { rxNotify_(); })) {}

void SimSerial::peerSend(std::string_view bytes) {
  onLine_.insert(onLine_.end(), bytes.begin(), bytes.end());
  if (!arriving_ && !onLine_.empty()) {
    arriving_ = true;
    clock_.scheduleIn(fw::us(static_cast<uint32_t>(byteTimeUs())), [this] { arrive(); });
  }
}

// One byte's stop bit has arrived.
void SimSerial::arrive() {
  const uint8_t byte = onLine_.front();
  onLine_.pop_front();
  ++received_;
  if (rx_.size() < rxDepth_) {
    rx_.push_back(byte);
  } else {
    ++lost_;
  }
  irq_.raise(rxLine_);
  if (onLine_.empty()) {
    arriving_ = false;
  } else {
    clock_.scheduleIn(fw::us(static_cast<uint32_t>(byteTimeUs())), [this] { arrive(); });
  }
}

bool SimSerial::doRead(uint8_t& byte) {
  if (rx_.empty()) return false;
  byte = rx_.front();
  rx_.pop_front();
  return true;
}

fw::Status SimSerial::doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) {
  if (busy_) return fw::Status::Busy;
  if (bytes.empty()) return fw::Status::InvalidArgument;
  busy_ = true;
  done_ = done;
  writeStarts_.push_back(text_.size());
  text_.append(bytes.begin(), bytes.end());
  const uint64_t us = (bytes.size() * 10ULL * 1000000ULL + baud_ - 1) / baud_;
  writeTimes_.push_back(clock_.nowUs() + us);
  clock_.scheduleIn(fw::us(static_cast<uint32_t>(us)), [this] { irq_.raise(line_); });
  return fw::Status::Ok;
}

SimEdgeInput::SimEdgeInput(SimIrq& irq, std::string name, Edge edge, bool initialLevel)
    : irq_(irq),
      line_(irq.attach(std::move(name), [this] { notify_(); })),
      edge_(edge),
      level_(initialLevel) {}

void SimEdgeInput::drive(bool level) {
  if (level == level_) return;
  level_ = level;
  const bool matches = (edge_ == Edge::Rising) == level;
  if (matches) {
    ++edges_;
    irq_.raise(line_);
  }
}

void SimDigitalOut::doSet(bool high) {
  if (high != level_ || history_.empty()) history_.emplace_back(clock_.nowUs(), high);
  level_ = high;
}

void SimSystem::doEnterBootloader() {
  entries_.push_back(clock_.nowUs());
}

void SimWatchdog::doFeed() {
  feeds_.push_back(clock_.nowUs());
}

uint64_t SimWatchdog::longestGapUs(uint64_t fromUs) const {
  uint64_t last = fromUs;
  uint64_t longest = 0;
  for (uint64_t t : feeds_) {
    if (t < fromUs) continue;
    longest = std::max(longest, t - last);
    last = t;
  }
  return std::max(longest, clock_.nowUs() - last);
}

}  // namespace bsp::host
