// SlcanLink: the command task's line on the L1306 images: bytes from the back-channel UART's receiver, read
// as SLCAN lines (slcan_adapter.hpp); the adapter's answer and the command answers, as SLCAN text, through
// the SLCAN publisher's outbox (app/publish/outbox.hpp), in one write.
#pragma once

#include "app/command/handler.hpp"
#include "app/command/slcan_adapter.hpp"
#include "app/publish/outbox.hpp"
#include "core/zeroed.hpp"
#include "hal/serial.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::command {

class SlcanLink {
 public:
  SlcanLink(hal::SerialRx& rx, SlcanOutbox& outbox, const hal::SystemControl& system)
      : rx_(rx), outbox_(outbox), system_(system) {}

  void attach(sched::Scheduler& s) {
    state_->serial = static_cast<uint16_t>(system_.identity().traceId);  // N's answer
    rx_.onReceive(s.notifier(kCommandTask, command_event::kInput));
  }
  bool outboxEmpty() const { return outbox_.length == 0; }
  void waitForOutbox() { outbox_.waiting = true; }
  // Reads up to the end of one line and answers it; false when no byte was waiting.
  bool step(CommandHandler& handler, sched::Scheduler& s);
  void send(const Replies& r, sched::Scheduler& s) { send(nullptr, 0, r, s); }
  const SlcanAdapter& adapter() const { return state_->adapter; }

 private:
  void send(const uint8_t* answer, uint8_t length, const Replies& r, sched::Scheduler& s);

  struct State {
    uint32_t lostAtLastF;  // SerialRx::lost() when F last answered
    uint16_t serial;       // the low 16 bits of the chip's TraceId
    SlcanAdapter adapter;
  };
  hal::SerialRx& rx_;
  SlcanOutbox& outbox_;
  const hal::SystemControl& system_;
  Zeroed<State> state_;
};

}  // namespace fw::app::command
