// CanLink: the command task's bus on the G3507 images: frames from the CAN controller (its filter passes the
// command identifiers only), answers through the CAN publisher's outbox (app/publish/outbox.hpp).
#pragma once

#include "app/command/handler.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/outbox.hpp"
#include "hal/can_bus.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::command {

class CanLink {
 public:
  CanLink(hal::CanBus& bus, CanOutbox& outbox, const hal::SystemControl&) : bus_(bus), outbox_(outbox) {}

  void attach(sched::Scheduler& s) { bus_.onReceive(s.notifier(kCommandTask, command_event::kInput)); }
  bool outboxEmpty() const { return outbox_.count == 0; }
  void waitForOutbox() { outbox_.waiting = true; }
  // One received frame through the handler; false when none was waiting.
  bool step(CommandHandler& handler, sched::Scheduler& s) {
    hal::CanFrame f;
    if (!bus_.receive(f)) return false;
    Replies r{};
    handler.handle(f, r);
    send(r, s);
    return true;
  }
  void send(const Replies& r, sched::Scheduler& s) {
    if (r.count == 0) return;
    for (uint8_t k = 0; k < r.count; ++k)
      outbox_.frames[k] = r.frame[k];
    outbox_.next = 0;
    outbox_.count = r.count;
    s.post(kPublisherTask, CanPublisher::kReply);
  }

 private:
  hal::CanBus& bus_;
  CanOutbox& outbox_;
};

}  // namespace fw::app::command
