// CommandTask<Link>: the commands a BMS takes (firmware/app/can/bms.yaml, direction rx) from its bus or line
// (Link: CanLink on the G3507 images, SlcanLink on the L1306 images), checked and acted on by the
// CommandHandler (handler.hpp: the checks and the safety rules), answered through the publisher's outbox.
//
// The lowest-priority task (app/tasks.hpp): it runs only when protection, the monitor and the publisher have
// nothing to do, and it handles one frame or line per run before giving way, so a flood of commands delays
// nothing else by more than one short run. It takes input only while the outbox is empty (one answer set at
// a time): a flood that produces answers faster than the publisher sends them waits in the controller's
// receive FIFO or the UART's buffer, which drop (and count) what does not fit.
// Bootloader entry: the handler's timer polls every CommandHandler::kPoll until the paths are confirmed off,
// then until the answer has left the outbox and kDrainPolls more, then the record store writes what must
// survive (BackgroundWork::beforeReset) and the MCU restarts (handler.hpp).
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
  static constexpr uint8_t kDrainPolls = 2;  // polls between the answer leaving the outbox and the restart

  template <class... LinkArgs>
  explicit CommandTask(const CommandHandler::Context& context, LinkArgs&&... linkArgs)
      : link_(static_cast<LinkArgs&&>(linkArgs)...), handler_(context) {}

  void start() {
    scheduler().addTask(kCommandTask, *this);
    link_.attach(scheduler());
  }

  // One frame or line per run, then the task posts itself again: every other task that became ready in
  // between runs first.
  void run(sched::EventMask events) override {
    if constexpr (FW_RECORD_STORE != 0) {
      if ((events & command_event::kStore) != 0 && background_.to != nullptr) background_.to->step();
    }
    if ((events & command_event::kTimer) != 0) bootStep();
    if (!link_.outboxEmpty()) return link_.waitForOutbox();
    if (link_.step(handler_, scheduler())) scheduler().post(kCommandTask, command_event::kInput);
  }

  const CommandHandler& handler() const { return handler_; }
  void setBalancing(BalancingPolicy& policy, const PackView& pack) { handler_.setBalancing(policy, pack); }
  void setStorage(StorageState& storage) { handler_.setStorage(storage); }
  // Images with the record store (FW_RECORD_STORE) only: its flash jobs run here, the lowest priority.
  void setBackground(BackgroundWork& work) { background_.set(work); }
  const Link& link() const { return link_; }

 private:
  sched::Scheduler& scheduler() { return handler_.scheduler(); }
  void bootStep() {
    if (!link_.outboxEmpty()) return;  // the outbox is still busy: next poll
    if (handler_.boot() == CommandHandler::Boot::WaitingForPaths) {
      Replies r{};
      handler_.poll(r);
      link_.send(r, scheduler());
    } else if (handler_.boot() == CommandHandler::Boot::Answered && ++drained_ >= kDrainPolls) {
      // The record store keeps what is waiting and the state of charge before the reset (the paths are off).
      if constexpr (FW_RECORD_STORE != 0) {
        if (background_.to != nullptr) background_.to->beforeReset();
      }
      handler_.answerSent();
    }
  }

  // The link first: the line's bytes the run loop touches most sit within Thumb's short reach of `this`
  // (-8 B on the full L1306-BQ76952 build against the handler first).
  Link link_;
  CommandHandler handler_;
  uint8_t drained_ = 0;
  [[no_unique_address]] StoreHook<BackgroundWork> background_{};
};

}  // namespace fw::app::command
