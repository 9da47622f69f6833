// SlcanLink: the command task's line on the L1306 images: bytes from the back-channel UART's receiver, read
// as SLCAN lines (slcan_adapter.hpp); the adapter's answer and the command answers, as SLCAN text, through
// the SLCAN publisher's outbox (app/publish/outbox.hpp), in one write.
#pragma once

#include "app/command/handler.hpp"
#include "app/command/slcan_adapter.hpp"
#include "app/publish/outbox.hpp"
#include "hal/serial.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::command {

class SlcanLink {
 public:
  SlcanLink(hal::SerialRx& rx, SlcanOutbox& outbox, uint16_t serial)
      : rx_(rx), outbox_(outbox), serial_(serial) {}

  void attach(sched::Scheduler& s) { rx_.onReceive(s.notifier(kCommandTask, command_event::kInput)); }
  bool outboxEmpty() const { return outbox_.length == 0; }
  void waitForOutbox() { outbox_.waiting = true; }
  // Reads up to the end of one line and answers it; false when no byte was waiting.
  bool step(CommandHandler& handler, sched::Scheduler& s);
  void send(const Replies& r, sched::Scheduler& s) { send(nullptr, 0, r, s); }
  const SlcanAdapter& adapter() const { return adapter_; }

 private:
  void send(const uint8_t* answer, uint8_t length, const Replies& r, sched::Scheduler& s);

  hal::SerialRx& rx_;
  SlcanOutbox& outbox_;
  uint16_t serial_;
  uint32_t lostAtLastF_ = 0;  // SerialRx::lost() when F last answered
  SlcanAdapter adapter_;
};

}  // namespace fw::app::command
