#include "app/can_publisher.hpp"

namespace fw::app {

void CanPublisher::run(sched::EventMask events) {
  if (can_.state() == hal::CanState::BusOff) {
    if (plan_.active()) {
      plan_.abandon();
      ++s_.stats.abandoned;
    }
    if (!s_.recovering) {
      ++s_.stats.busOff;
      s_.recovering = true;
      can_.recover();
    } else if ((events & kTick) != 0) {
      can_.recover();  // retry once per fast period while the bus stays off
    }
    return;
  }
  s_.recovering = false;

  // A new cycle: native on the tick (slow every slowEvery ticks), TI after each scan (none while a set is
  // still going out: sets go out whole).
  const Instant now = scheduler_.now();
  const bool ti = layout_ == CanLayout::Ti;
  if ((events & (ti ? kScanDone : kTick)) != 0) {
    if (ti) {
      plan_.beginTi();
    } else if (plan_.beginNative(s_.tick, slowEvery_)) {
      ++s_.stats.abandoned;
    }
    ++s_.stats.cycles;
  }
  pump(now);
}

inline void CanPublisher::pump(Instant now) {
  hal::CanFrame frame;
  while (plan_.build(now, frame)) {
    const Status s = can_.send(frame);
    if (s == Status::Ok) {
      ++s_.stats.frames;
      plan_.advance();
      continue;
    }
    if (s == Status::Overflow) {
      ++s_.stats.refused;  // wait for a frame to leave (kCan)
    } else {
      plan_.abandon();  // BusOff or a malformed frame: drop the cycle, the next one starts fresh
      ++s_.stats.abandoned;
    }
    return;
  }
}

}  // namespace fw::app
