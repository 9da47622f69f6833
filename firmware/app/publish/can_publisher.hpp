// CanPublisher: sends the publish cycles of a FramePlan on a CAN bus (the G3507 images).
//
// Native layout: a fast cycle every `fastPeriod` and a slow one every `slowEvery` fast periods (a slow part
// longer than a fast period continues after the next fast frames: frame_plan.hpp). TI layout: one set per
// new scan (post kScanDone), as TI's demo sends after each read, and only whole sets.
// The task fills the controller's TX queue until it refuses (Overflow) and continues when a frame has left
// (kCan), so it never waits. One run queues at most kFramesPerRun frames (answers and plan frames together)
// and posts itself (kMore) for the rest: the scheduler never preempts a run, and a run that filled the whole
// 8-frame queue (about 0.5 ms on the G3507 at 32 MHz, measured on the twin) held up every higher task that
// became ready meanwhile: the FET-off command's echo poll (ALERT to the command complete, worst over the
// scan, 1 935 us; 1 669 us with one frame a run). Frames still unsent when the
// next cycle drops them (frame_plan.hpp) count as an abandoned cycle: the bus is saturated, and newer data is
// worth more than older frames. The command task's answers (outbox(), app/publish/outbox.hpp; post kReply)
// are queued ahead of the plan's next frames, one answer set at a time. On bus-off it abandons the cycle (and
// drops each cycle due while the bus is off, so PackSummary.Counter shows every summary that never went out),
// starts the controller's recovery (at most once per fast period) and resumes with fresh frames when the bus
// is back. Thread mode only.
#pragma once

#include <cstdint>

#include "app/publish/frame_plan.hpp"
#include "app/publish/outbox.hpp"
#include "core/zeroed.hpp"
#include "hal/can_bus.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

struct PublishStats {
  uint32_t frames = 0;     // frames accepted by the bus
  uint32_t cycles = 0;     // cycles started
  uint32_t abandoned = 0;  // cycles dropped unfinished (saturated bus or bus-off)
  uint32_t busOff = 0;     // bus-off events seen (each starts a recovery)
  uint32_t refused = 0;    // send attempts refused (queue full)
  uint32_t answers = 0;    // command answers sent (frames on CAN, writes on SLCAN)
};

class CanPublisher final : public sched::Task {
 public:
  static constexpr sched::EventMask kScanDone = 0x1;
  static constexpr sched::EventMask kCan = 0x2;
  static constexpr sched::EventMask kReply = 0x8;
  // Frames one run queues at most (see above): a frame's run is about 70 us of CPU on the G3507 (twin), well
  // ahead of the bus (a frame takes about 0.25 ms at 500 kbit/s), so the queue still fills in a cycle's
  // first runs.
  static constexpr uint8_t kFramesPerRun = 1;

  // Inline: an image constructs it once, and the constructor is then stores only.
  CanPublisher(sched::Scheduler& scheduler, sched::TaskId id, hal::CanBus& can, FramePlan& plan,
               CanLayout layout, Duration fastPeriod, uint8_t slowEvery)
      : id_(id),
        layout_(layout),
        slowEvery_(slowEvery == 0 ? 1 : slowEvery),
        scheduler_(scheduler),
        can_(can),
        plan_(plan),
        fastPeriod_(fastPeriod) {}

  void start() {
    scheduler_.addTask(id_, *this);
    can_.onEvent(scheduler_.notifier(id_, kCan));
    // The TI layout also sends its summary-free stream only after scans; the timer still drives bus-off
    // recovery in both layouts.
    scheduler_.startTimer(state_->timer, id_, kTick, fastPeriod_, fastPeriod_);
  }
  void run(sched::EventMask events) override;
  const PublishStats& stats() const { return state_->stats; }
  CanOutbox& outbox() { return state_->outbox; }

 private:
  static constexpr sched::EventMask kTick = 0x4;
  static constexpr sched::EventMask kMore = 0x10;  // the last run stopped at kFramesPerRun with more to send
  inline void pump(Instant now);
  // Queues the waiting answers within `budget` frames; false when it stopped: the controller refused one
  // (queue full) or the budget ran out.
  inline bool sendAnswers(uint8_t& budget);
  // The queue is still full: it refused a frame, and since then no more frames have left it (the controller's
  // txFrames, `left`) than this task queued. This task is the controller's only sender, so the count holds; a
  // frame built now would only be refused, and built again once one has left (kCan).
  bool queueFull(uint32_t left) const {
    const State& st = *state_;
    return st.counting && left - st.leftAtFull <= st.queuedSince;
  }
  // A send's result for the count above, with txFrames as read before the send: Overflow starts the count
  // afresh (the queue was full with `left` frames gone; read after the refusal, a frame leaving in between
  // would be counted as gone before the queue was full, and the count would wait for one frame too many),
  // Ok counts a frame.
  Status counted(Status s, uint32_t left) {
    State& st = *state_;
    if (s == Status::Ok) {
      ++st.queuedSince;
    } else if (s == Status::Overflow) {
      st.counting = true;
      st.leftAtFull = left;
      st.queuedSince = 0;
    }
    return s;
  }
  // The run's frame budget is spent and there is more: continue in a new run (after any higher task).
  bool yieldFor(uint8_t budget) {
    if (budget != 0) return false;
    scheduler_.post(id_, kMore);
    return true;
  }

  // What changes, zero at construction (one block, no per-member start-up code), after the byte fields
  // (Cortex-M0+ byte loads reach only 31 bytes past the object's address) and the references.
  struct State {
    uint8_t tick;
    bool recovering;
    bool counting;  // the queue refused a frame since the last bus-off: its room is counted (queueFull())
    uint32_t busOffsSeen;  // the controller's bus-off count when recovery was last asked for
    uint32_t leftAtFull;   // the controller's txFrames before the send the queue last refused
    uint32_t queuedSince;  // frames this task queued since then
    sched::Timer timer;
    PublishStats stats;
    CanOutbox outbox;
  };
  sched::TaskId id_;
  CanLayout layout_;
  uint8_t slowEvery_;
  sched::Scheduler& scheduler_;
  hal::CanBus& can_;
  FramePlan& plan_;
  Duration fastPeriod_;
  Zeroed<State> state_;
};

}  // namespace fw::app
