#include "app/publish/slcan_publisher.hpp"

#include "core/stats.hpp"

namespace fw::app {

void SlcanPublisher::run(sched::EventMask events) {
  if ((events & kSent) != 0) {
    state_->busy = false;
    SlcanOutbox& box = state_->outbox;
    if (box.inFlight) {  // the answers have left: the outbox is the command task's again
      box.inFlight = false;
      box.length = 0;
      if (box.waiting) {
        box.waiting = false;
        scheduler_.post(kCommandTask, command_event::kOutboxFree);
      }
      if (kStats) ++state_->stats.answers;
    } else if (kStats) {
      ++state_->stats.frames;
    }
  }
  if ((events & kTick) != 0) {
    const bool dropped = plan_.beginNative(state_->tick, slowEvery_);
    if (kStats && dropped) ++state_->stats.abandoned;
    if (kStats) ++state_->stats.cycles;
  }
  pump(scheduler_.now());
}

void SlcanPublisher::pump(Instant now) {
  if (state_->busy) return;
  if (!state_->answered && sendAnswer()) return;
  std::array<uint8_t, 8> data;
  const uint16_t id = plan_.fill(now, data);
  if (id == 0) {
    sendAnswer();
    return;
  }
  slcan::encodeStandard(id, data, state_->line);
  if (!write(state_->line)) {
    plan_.abandon();
    return;
  }
  // The line is the transmitter's now (state_->line stays untouched until kSent): the plan moves on at once,
  // so a tick while it is on the wire begins the next cycle from the right place.
  plan_.advance();
  state_->answered = false;
}

// The outbox's text in one write, if any waits; true if it went.
bool SlcanPublisher::sendAnswer() {
  SlcanOutbox& box = state_->outbox;
  if (box.length == 0 || !write({box.text, box.length})) return false;
  box.inFlight = true;
  state_->answered = true;
  return true;
}

// Hands `text` to the line (busy until kSent); false, and counted, if the line refused it.
bool SlcanPublisher::write(std::span<const uint8_t> text) {
  if (serial_.write(text, scheduler_.notifier(id_, kSent)) != Status::Ok) {
    if (kStats) ++state_->stats.refused;
    return false;
  }
  state_->busy = true;
  return true;
}

}  // namespace fw::app
