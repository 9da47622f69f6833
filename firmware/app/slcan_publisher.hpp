// SlcanPublisher: sends the publish cycles of a FramePlan as SLCAN text lines on a serial transmitter (the
// L1306 images: the XDS110 back-channel UART), so a PC reads them with slcand / python-can as a CAN bus.
//
// One line is in flight at a time; the next is built (from the live pack) when the previous has left, so
// nothing waits and nothing stale is sent. A cycle still unfinished when the next is due is abandoned
// (counted). Thread mode only.
#pragma once

#include <cstdint>

#include "app/can_publisher.hpp"
#include "app/frame_plan.hpp"
#include "app/slcan.hpp"
#include "hal/serial.hpp"
#include "sched/scheduler.hpp"

namespace fw::app {

class SlcanPublisher final : public sched::Task {
 public:
  static constexpr sched::EventMask kScanDone = 0x1;

  SlcanPublisher(sched::Scheduler& scheduler, sched::TaskId id, hal::SerialTx& serial, FramePlan& plan,
                 Duration fastPeriod, uint8_t slowEvery);

  void start();
  void run(sched::EventMask events) override;
  const PublishStats& stats() const { return stats_; }

 private:
  static constexpr sched::EventMask kTick = 0x2;
  static constexpr sched::EventMask kSent = 0x4;
  void pump(Instant now);

  sched::Scheduler& scheduler_;
  sched::TaskId id_;
  hal::SerialTx& serial_;
  FramePlan& plan_;
  Duration fastPeriod_;
  uint8_t slowEvery_;
  uint8_t tick_ = 0;
  bool busy_ = false;
  bool lineFromOldCycle_ = false;  // the line in flight was built before the current cycle began
  sched::Timer timer_;
  PublishStats stats_;
  uint8_t line_[slcan::kMaxEncodedLength];
};

}  // namespace fw::app
