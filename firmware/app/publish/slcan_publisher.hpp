// SlcanPublisher: sends the publish cycles of a FramePlan as SLCAN text lines on a serial transmitter (the
// L1306 images: the XDS110 back-channel UART), so a PC reads them with slcand / python-can as a CAN bus.
//
// One line is in flight at a time; the next is built (from the live pack) when the previous has left, so
// nothing waits and nothing stale is sent. Cycles follow FramePlan (a slow part continues after the next
// fast frames); frames a new cycle drops count as an abandoned cycle. The command task's answers (outbox(),
// app/publish/outbox.hpp; post kReply) go out between the lines, never twice in a row while a line of the
// plan is due. Thread mode only.
#pragma once

#include <cstdint>
#include <span>

#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/outbox.hpp"
#include "app/publish/slcan.hpp"
#include "core/zeroed.hpp"
#include "hal/serial.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

class SlcanPublisher final : public sched::Task {
 public:
  // Its cycles run on the timer alone: a finished scan needs no event (0: the monitor posts none).
  static constexpr sched::EventMask kScanDone = 0;

  // Inline: an image constructs it once, and the constructor is then stores only.
  SlcanPublisher(sched::Scheduler& scheduler, sched::TaskId id, hal::SerialTx& serial, FramePlan& plan,
                 Duration fastPeriod, uint8_t slowEvery)
      : id_(id),
        slowEvery_(slowEvery == 0 ? 1 : slowEvery),
        scheduler_(scheduler),
        serial_(serial),
        plan_(plan),
        fastPeriod_(fastPeriod) {}

  static constexpr sched::EventMask kReply = 0x8;

  void start() {
    scheduler_.addTask(id_, *this);
    scheduler_.startTimer(state_->timer, id_, kTick, fastPeriod_, fastPeriod_);
  }
  void run(sched::EventMask events) override;
  const PublishStats& stats() const { return state_->stats; }
  SlcanOutbox& outbox() { return state_->outbox; }

 private:
  static constexpr sched::EventMask kTick = 0x2;
  static constexpr sched::EventMask kSent = 0x4;
  void pump(Instant now);
  bool sendAnswer();
  bool write(std::span<const uint8_t> text);

  // What changes, zero at construction (one block, no per-member start-up code); byte fields first
  // (Cortex-M0+ byte loads reach only 31 bytes past the object's address).
  struct State {
    uint8_t tick;
    bool busy;
    bool answered;  // the last write was an answer: a due line of the plan goes next
    uint8_t line[slcan::kStandardLength];
    sched::Timer timer;
    PublishStats stats;
    SlcanOutbox outbox;
  };
  sched::TaskId id_;
  uint8_t slowEvery_;
  Zeroed<State> state_;
  sched::Scheduler& scheduler_;
  hal::SerialTx& serial_;
  FramePlan& plan_;
  Duration fastPeriod_;
};

}  // namespace fw::app
