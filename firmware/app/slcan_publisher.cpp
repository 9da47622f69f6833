#include "app/slcan_publisher.hpp"

#include "core/stats.hpp"

namespace fw::app {

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    s_.busy = false;
    if (kStats) ++s_.stats.frames;
  }
  if ((events & kTick) != 0) {
    const bool dropped = plan_.beginNative(s_.tick, slowEvery_);
    if (kStats && dropped) ++s_.stats.abandoned;
    if (kStats) ++s_.stats.cycles;
  }
  pump(scheduler_.now());
}

void SlcanPublisher::pump(Instant now) {
  if (s_.busy) return;
  std::array<uint8_t, 8> data;
  const uint16_t id = plan_.fill(now, data);
  if (id == 0) return;
  slcan::encodeStandard(id, data, s_.line);
  if (serial_.write(s_.line, scheduler_.notifier(id_, kSent)) != Status::Ok) {
    if (kStats) ++s_.stats.refused;
    plan_.abandon();
    return;
  }
  // The line is the transmitter's now (s_.line stays untouched until kSent): the plan moves on at once, so a
  // tick while it is on the wire begins the next cycle from the right place.
  plan_.advance();
  s_.busy = true;
}

}  // namespace fw::app
