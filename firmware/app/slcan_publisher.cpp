#include "app/slcan_publisher.hpp"

namespace fw::app {

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    s_.busy = false;
    if (!s_.lineFromOldCycle) plan_.advance();  // the line built from the current frame has left
    s_.lineFromOldCycle = false;
    ++s_.stats.frames;
  }
  if ((events & kTick) != 0) {
    if (plan_.active()) ++s_.stats.abandoned;
    s_.lineFromOldCycle = s_.busy;
    if (s_.tick == 0) {
      plan_.beginSlow();
    } else {
      plan_.beginFast();
    }
    if (++s_.tick == slowEvery_) s_.tick = 0;
    ++s_.stats.cycles;
  }
  pump(scheduler_.clock().now());
}

void SlcanPublisher::pump(Instant now) {
  if (s_.busy) return;
  hal::CanFrame frame;
  if (!plan_.build(now, frame)) return;
  const size_t n = slcan::encode(frame, s_.line);
  if (n == 0 || serial_.write({s_.line, n}, scheduler_.notifier(id_, kSent)) != Status::Ok) {
    ++s_.stats.refused;
    plan_.abandon();
    return;
  }
  s_.busy = true;
}

}  // namespace fw::app
