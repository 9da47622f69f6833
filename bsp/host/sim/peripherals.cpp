#include "sim/peripherals.hpp"

#include <algorithm>

#include "sim/sim_clock.hpp"
#include "sim/sim_irq.hpp"

namespace bsp::host {

SimSerialTx::SimSerialTx(SimClock& clock, SimIrq& irq, uint32_t baud)
    : clock_(clock), irq_(irq), baud_(baud), line_(irq.attach("serial", [this] {
        busy_ = false;
        fw::hal::Notify done = done_;
        done_ = {};
        done();
      })) {}

fw::Status SimSerialTx::doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) {
  if (busy_) return fw::Status::Busy;
  if (bytes.empty()) return fw::Status::InvalidArgument;
  busy_ = true;
  done_ = done;
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
