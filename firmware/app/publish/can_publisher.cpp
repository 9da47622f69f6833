#include "app/publish/can_publisher.hpp"

namespace fw::app {

void CanPublisher::run(sched::EventMask events) {
  // A new cycle: native on the tick (slow every slowEvery ticks), TI after each scan (none while a set is
  // still going out: sets go out whole). It begins during a bus-off too and is dropped at once below, so the
  // PackSummary it would have carried leaves its Counter gap (frame_plan.hpp), as one lost in the controller.
  const bool ti = layout_ == CanLayout::Ti;
  if ((events & (ti ? kScanDone : kTick)) != 0) {
    if (ti) {
      plan_.beginTi();
    } else if (plan_.beginNative(state_->tick, slowEvery_)) {
      ++state_->stats.abandoned;
    }
    ++state_->stats.cycles;
  }
  if (can_.state() == hal::CanState::BusOff) {
    if (plan_.active()) {
      plan_.abandon();
      ++state_->stats.abandoned;
    }
    // A bus-off the controller counted since recovery was last asked for is a new one, even when this task
    // never saw the bus on in between (it can come microseconds after a recovery, before this task ran):
    // recover at once, not a publish period later.
    const uint32_t busOffs = can_.counters().busOffEvents;
    state_->counting = false;  // whatever the controller does with its queue now, the next refusal says
    if (!state_->recovering || busOffs != state_->busOffsSeen) {
      ++state_->stats.busOff;
      state_->recovering = true;
      state_->busOffsSeen = busOffs;
      // Busy (a recovery is under way) or NotReady are answered by the retry below: ignoring them is safe.
      (void)can_.recover();
    } else if ((events & kTick) != 0) {
      (void)can_.recover();  // retry once per fast period while the bus stays off: a refusal is retried too
    }
    return;
  }
  state_->recovering = false;
  pump(scheduler_.now());
}

inline void CanPublisher::pump(Instant now) {
  uint8_t budget = kFramesPerRun;
  if (!sendAnswers(budget)) return;
  hal::CanFrame frame;
  for (;;) {
    // The queue's room and the budget before build(): a frame is filled only when this run sends it, not
    // once more next run. (Built into a full queue, every frame of a 64-board cycle was filled twice: 10 %
    // of the 64-device BQ79616 image's busy cycles, twin profile.)
    const uint32_t left = can_.counters().txFrames;
    if (plan_.active() && (queueFull(left) || yieldFor(budget))) return;
    if (!plan_.build(now, frame)) return;
    const Status s = counted(can_.send(frame), left);
    if (s == Status::Ok) {
      ++state_->stats.frames;
      plan_.advance();
      --budget;
      continue;
    }
    if (s == Status::Overflow) {
      ++state_->stats.refused;  // wait for a frame to leave (kCan)
    } else {
      plan_.abandon();  // BusOff or a malformed frame: drop the cycle, the next one starts fresh
      ++state_->stats.abandoned;
    }
    return;
  }
}

// The waiting answers into the controller's queue; when the last has gone the outbox is the command task's
// again. An answer the controller cannot take for good (bus-off) is dropped with the rest of its set.
inline bool CanPublisher::sendAnswers(uint8_t& budget) {
  CanOutbox& box = state_->outbox;
  while (box.count != 0) {
    if (yieldFor(budget)) return false;
    --budget;
    const uint32_t left = can_.counters().txFrames;
    const Status s = counted(can_.send(box.frames[box.next]), left);
    if (s == Status::Overflow) {
      ++state_->stats.refused;
      return false;
    }
    if (s == Status::Ok) ++state_->stats.answers;
    ++box.next;
    if (--box.count == 0 && box.waiting) {
      box.waiting = false;
      scheduler_.post(kCommandTask, command_event::kOutboxFree);
    }
  }
  return true;
}

}  // namespace fw::app
