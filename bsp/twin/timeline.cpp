#include "timeline.hpp"

#include <algorithm>

namespace twin {

TimedEvent::TimedEvent(Timeline& timeline, std::function<void()> action)
    : timeline_(timeline), action_(std::move(action)) {
  timeline_.attach(this);
}

TimedEvent::~TimedEvent() {
  timeline_.detach(this);
}

void TimedEvent::at(uint64_t cycle) {
  at_ = cycle;
  order_ = timeline_.order_++;
  armed_ = true;
  timeline_.rearmed_ = true;
}

void TimedEvent::after(uint64_t cycles) {
  at(timeline_.now() + cycles);
}

void Timeline::detach(TimedEvent* e) {
  events_.erase(std::remove(events_.begin(), events_.end(), e), events_.end());
}

uint64_t Timeline::next() const {
  uint64_t t = UINT64_MAX;
  for (const TimedEvent* e : events_) {
    if (e->armed_ && e->at_ < t) t = e->at_;
  }
  return t;
}

bool Timeline::fireNext(uint64_t limit) {
  TimedEvent* first = nullptr;
  for (TimedEvent* e : events_) {
    if (!e->armed_ || e->at_ > limit) continue;
    if (first == nullptr || e->at_ < first->at_ || (e->at_ == first->at_ && e->order_ < first->order_))
      first = e;
  }
  if (first == nullptr) return false;
  first->armed_ = false;
  // The action runs at the event's own time, so what it schedules next does not drift; the CPU may have
  // finished an instruction past that time, and time resumes from the later of the two.
  const uint64_t saved = now_;
  now_ = first->at_;
  first->action_();
  now_ = std::max(now_, saved);
  return true;
}

}  // namespace twin
