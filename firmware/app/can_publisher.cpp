#include "app/can_publisher.hpp"

namespace fw::app {

CanPublisher::CanPublisher(sched::Scheduler& scheduler, sched::TaskId id, hal::CanBus& can, FramePlan& plan,
                           CanLayout layout, Duration fastPeriod, uint8_t slowEvery)
    : scheduler_(scheduler),
      id_(id),
      can_(can),
      plan_(plan),
      layout_(layout),
      fastPeriod_(fastPeriod),
      slowEvery_(slowEvery == 0 ? 1 : slowEvery) {}

void CanPublisher::start() {
  scheduler_.addTask(id_, *this);
  can_.onEvent(scheduler_.notifier(id_, kCan));
  // The TI layout also sends its summary-free stream only after scans; the timer still drives bus-off
  // recovery in both layouts.
  scheduler_.startTimer(timer_, id_, kTick, fastPeriod_, fastPeriod_);
}

void CanPublisher::beginCycle(bool ti) {
  if (plan_.active()) ++stats_.abandoned;
  if (ti) {
    plan_.beginTi();
  } else if (tick_ == 0) {
    plan_.beginSlow();
  } else {
    plan_.beginFast();
  }
  ++stats_.cycles;
}

void CanPublisher::run(sched::EventMask events) {
  const Instant now = scheduler_.clock().now();
  const hal::CanState state = can_.state();
  if (state == hal::CanState::BusOff) {
    if (plan_.active()) {
      plan_.abandon();
      ++stats_.abandoned;
    }
    if (!recovering_) {
      ++stats_.busOff;
      recovering_ = true;
      ++stats_.recoveries;
      can_.recover();
    } else if ((events & kTick) != 0) {
      can_.recover();  // retry once per fast period while the bus stays off
    }
    return;
  }
  recovering_ = false;

  if ((events & kTick) != 0 && layout_ == CanLayout::Native) {
    beginCycle(false);
    tick_ = static_cast<uint8_t>((tick_ + 1) % slowEvery_);
  }
  if ((events & kScanDone) != 0 && layout_ == CanLayout::Ti) beginCycle(true);
  pump(now);
}

void CanPublisher::pump(Instant now) {
  hal::CanFrame frame;
  while (plan_.build(now, frame)) {
    const Status s = can_.send(frame);
    if (s == Status::Ok) {
      ++stats_.frames;
      plan_.advance();
      continue;
    }
    if (s == Status::Overflow) {
      ++stats_.refused;  // wait for a frame to leave (kCan)
    } else {
      plan_.abandon();  // BusOff or a malformed frame: drop the cycle, the next one starts fresh
      ++stats_.abandoned;
    }
    return;
  }
}

}  // namespace fw::app
