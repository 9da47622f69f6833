#include "app/slcan_publisher.hpp"

#include "core/stats.hpp"

namespace fw::app {

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    s_.busy = false;
    if (!s_.lineFromOldCycle) plan_.advance();  // the line built from the current frame has left
    s_.lineFromOldCycle = false;
    if (kStats) ++s_.stats.frames;
  }
  if ((events & kTick) != 0) {
    if (kStats && plan_.active()) ++s_.stats.abandoned;
    s_.lineFromOldCycle = s_.busy;
    plan_.beginNative(s_.tick, slowEvery_);
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
  s_.busy = true;
}

}  // namespace fw::app
