#include "sim/sim_clock.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "sim/sim_irq.hpp"

namespace bsp::host {

SimClock::SimClock(SimIrq& irq) : irq_(irq), timerLine_(irq.attach("timer", [] {})) {}

SimClock::EventId SimClock::schedule(uint64_t atUs, Callback callback) {
  if (atUs < now_) atUs = now_;
  const EventId id = nextSeq_++;
  events_.emplace(std::make_pair(atUs, id), std::move(callback));
  return id;
}

void SimClock::cancel(EventId id) {
  for (auto it = events_.begin(); it != events_.end(); ++it) {
    if (it->first.second == id) {
      events_.erase(it);
      return;
    }
  }
}

bool SimClock::nextEvent(uint64_t& atUs) const {
  if (events_.empty()) return false;
  atUs = events_.begin()->first.first;
  return true;
}

bool SimClock::step(uint64_t limitUs) {
  if (events_.empty() || events_.begin()->first.first > limitUs) return false;
  auto node = events_.extract(events_.begin());
  now_ = node.key().first;
  if (node.key().second == alarm_) alarm_ = 0;
  node.mapped()();
  return true;
}

void SimClock::advanceTo(uint64_t timeUs) {
  if (advancing_) {
    // An event callback advancing time would reorder events; it is a harness bug.
    std::fprintf(stderr, "SimClock: advanceTo called from inside a simulation event\n");
    std::abort();
  }
  if (timeUs < now_) return;
  advancing_ = true;
  while (step(timeUs)) {
  }
  now_ = timeUs;
  advancing_ = false;
}

void SimClock::advanceBefore(uint64_t timeUs) {
  if (timeUs <= now_) return;
  advanceTo(timeUs - 1);
  now_ = timeUs;
  // The alarm, if it falls on this microsecond, stays queued, but the firmware must see its deadline due as
  // the target would (a pending interrupt runs at once): the wake-up counts as fired.
  if (alarm_ != 0 && alarmAt_ <= now_) wakeFired();
}

uint64_t SimClock::expand(fw::Instant instant) const {
  const int32_t delta = static_cast<int32_t>(instant.us - static_cast<uint32_t>(now_));
  const int64_t at = static_cast<int64_t>(now_) + delta;
  return at < 0 ? 0 : static_cast<uint64_t>(at);
}

void SimClock::doWakeAt(fw::Instant deadline) {
  // The scheduler re-arms the alarm on every idle: erasing it by its key keeps that O(log n) with many device
  // events pending (a 64-device chain queues thousands).
  ++wakeAts_;
  if (alarm_ != 0) events_.erase({alarmAt_, alarm_});
  const int line = timerLine_;
  SimIrq* irq = &irq_;
  alarmAt_ = std::max(expand(deadline), now_);
  // The event is the compare match and its handler's bookkeeping together (wakeFired), as on the target.
  alarm_ = schedule(alarmAt_, [this, irq, line] {
    wakeFired();
    irq->raise(line);
  });
}

}  // namespace bsp::host
