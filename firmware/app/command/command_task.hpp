// CommandTask<Link>: the commands a BMS takes (firmware/app/can/bms.yaml, direction rx) from its bus or line
// (Link: CanLink on the G3507 images, SlcanLink on the L1306 images), checked and acted on by the
// CommandHandler (handler.hpp: the checks and the safety rules), answered through the publisher's outbox.
//
// The lowest-priority task (app/tasks.hpp): it runs only when protection, the monitor and the publisher have
// nothing to do, and it handles at most kPerRun frames or lines per run before giving way, so a flood of
// commands delays nothing else by more than one short run. It takes input only while the outbox is empty
// (one answer set at a time): a flood that produces answers faster than the publisher sends them waits in
// the controller's receive FIFO or the UART's buffer, which drop (and count) what does not fit.
// Bootloader entry polls every kPoll until the paths are confirmed off, then the answer has left (kDrain),
// then restarts the MCU (handler.hpp).
// Events: command_event::kInput (the receive Notify), kOutboxFree (the publisher), kTimer. Thread mode.
#pragma once

#include <cstdint>

#include "app/command/handler.hpp"
#include "app/tasks.hpp"
#include "core/zeroed.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::command {

template <class Link>
class CommandTask final : public sched::Task {
 public:
  static constexpr uint8_t kPerRun = 4;
  static constexpr Duration kPoll = ms(10);
  static constexpr uint8_t kDrainPolls = 2;  // polls between the answer leaving the outbox and the restart

  template <class... LinkArgs>
  CommandTask(sched::Scheduler& scheduler, const CommandHandler::Context& context, LinkArgs&&... linkArgs)
      : scheduler_(scheduler), handler_(context), link_(static_cast<LinkArgs&&>(linkArgs)...) {}

  [[gnu::always_inline]] void start() {  // one caller (the composition's start())
    scheduler_.addTask(kCommandTask, *this);
    link_.attach(scheduler_);
  }

  void run(sched::EventMask events) override {
    if ((events & command_event::kTimer) != 0) bootStep();
    for (uint8_t n = 0; n < kPerRun; ++n) {
      if (!link_.outboxEmpty()) return link_.waitForOutbox();
      const CommandHandler::Boot before = handler_.boot();
      if (!link_.step(handler_, scheduler_)) return;
      if (before == CommandHandler::Boot::Idle && handler_.boot() != before)
        scheduler_.startTimer(state_->timer, kCommandTask, command_event::kTimer, kPoll, kPoll);
    }
    scheduler_.post(kCommandTask, command_event::kInput);  // more may wait: every other task first
  }

  const CommandHandler& handler() const { return handler_; }
  const Link& link() const { return link_; }

 private:
  void bootStep() {
    if (!link_.outboxEmpty()) return;  // the outbox is still busy: next poll
    if (handler_.boot() == CommandHandler::Boot::WaitingForPaths) {
      Replies r{};
      handler_.poll(r);
      link_.send(r, scheduler_);
    } else if (handler_.boot() == CommandHandler::Boot::Answered && ++state_->drained >= kDrainPolls) {
      handler_.answerSent();
    }
    if (handler_.boot() == CommandHandler::Boot::Idle) scheduler_.stopTimer(state_->timer);
  }

  struct State {
    uint8_t drained;
    sched::Timer timer;
  };
  sched::Scheduler& scheduler_;
  Zeroed<State> state_;
  CommandHandler handler_;
  Link link_;
};

}  // namespace fw::app::command
