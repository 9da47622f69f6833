#include "app/publish/slcan_publisher.hpp"

#include "core/stats.hpp"

namespace fw::app {

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    state_->busy = false;
    if (kStats) ++state_->stats.frames;
  }
  if ((events & kTick) != 0) {
    const bool dropped = plan_.beginNative(state_->tick, slowEvery_);
    if (kStats && dropped) ++state_->stats.abandoned;
    if (kStats) ++state_->stats.cycles;
  }
  pump(scheduler_.now());
}

void SlcanPublisher::pump(Instant now) {
  if (state_->busy) return;
  std::array<uint8_t, 8> data;
  const uint16_t id = plan_.fill(now, data);
  if (id == 0) return;
  slcan::encodeStandard(id, data, state_->line);
  if (serial_.write(state_->line, scheduler_.notifier(id_, kSent)) != Status::Ok) {
    if (kStats) ++state_->stats.refused;
    plan_.abandon();
    return;
  }
  // The line is the transmitter's now (state_->line stays untouched until kSent): the plan moves on at once,
  // so a tick while it is on the wire begins the next cycle from the right place.
  plan_.advance();
  state_->busy = true;
}

}  // namespace fw::app
