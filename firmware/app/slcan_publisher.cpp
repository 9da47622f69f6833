#include "app/slcan_publisher.hpp"

namespace fw::app {

SlcanPublisher::SlcanPublisher(sched::Scheduler& scheduler, sched::TaskId id, hal::SerialTx& serial,
                               FramePlan& plan, Duration fastPeriod, uint8_t slowEvery)
    : scheduler_(scheduler),
      id_(id),
      serial_(serial),
      plan_(plan),
      fastPeriod_(fastPeriod),
      slowEvery_(slowEvery == 0 ? 1 : slowEvery) {}

void SlcanPublisher::start() {
  scheduler_.addTask(id_, *this);
  scheduler_.startTimer(timer_, id_, kTick, fastPeriod_, fastPeriod_);
}

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    busy_ = false;
    if (!lineFromOldCycle_) plan_.advance();  // the line built from the current frame has left
    lineFromOldCycle_ = false;
    ++stats_.frames;
  }
  if ((events & kTick) != 0) {
    if (plan_.active()) ++stats_.abandoned;
    lineFromOldCycle_ = busy_;
    if (tick_ == 0) {
      plan_.beginSlow();
    } else {
      plan_.beginFast();
    }
    tick_ = static_cast<uint8_t>((tick_ + 1) % slowEvery_);
    ++stats_.cycles;
  }
  pump(scheduler_.clock().now());
}

void SlcanPublisher::pump(Instant now) {
  if (busy_) return;
  hal::CanFrame frame;
  if (!plan_.build(now, frame)) return;
  const size_t n = slcan::encode(frame, line_);
  if (n == 0 || serial_.write({line_, n}, scheduler_.notifier(id_, kSent)) != Status::Ok) {
    ++stats_.refused;
    plan_.abandon();
    return;
  }
  busy_ = true;
}

}  // namespace fw::app
