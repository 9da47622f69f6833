#include "app/command/slcan_link.hpp"

#include <span>

#include "app/publish/slcan.hpp"
#include "app/publish/slcan_publisher.hpp"

namespace fw::app::command {

bool SlcanLink::step(CommandHandler& handler, sched::Scheduler& s) {
  uint8_t byte;
  bool any = false;
  State& st = *state_;
  while (rx_.read(byte)) {
    any = true;
    if (!st.adapter.take(byte)) continue;
    const uint32_t lost = rx_.lost();
    SlcanAdapter::Line line;
    st.adapter.answer({st.serial, lost != st.lostAtLastF}, line);
    if (line.answer[0] == 'F') st.lostAtLastF = lost;  // the flags were read: overrun is cleared
    Replies r{};
    if (line.hasFrame) handler.handle(line.frame, r);
    send(line.answer, line.answerLength, r, s);
    return true;
  }
  return any;
}

// Every answer frame is a standard 8-byte one (bms.yaml; handler.cpp checks it), so each is one line of
// slcan::kStandardLength bytes.
static_assert(SlcanAdapter::kMaxAnswer + Replies::kMax * app::slcan::kStandardLength <= SlcanOutbox::kBytes);
void SlcanLink::send(const uint8_t* answer, uint8_t length, const Replies& r, sched::Scheduler& s) {
  uint8_t* text = outbox_.text;
  for (uint32_t i = 0; i < length; ++i)
    *text++ = answer[i];
  for (const hal::CanFrame& f : std::span(r.frame, r.count)) {
    app::slcan::encodeStandard(static_cast<uint16_t>(f.id), f.data, text);
    text += app::slcan::kStandardLength;
  }
  if (text == outbox_.text) return;
  outbox_.length = static_cast<uint8_t>(text - outbox_.text);
  s.post(kPublisherTask, SlcanPublisher::kReply);
}

}  // namespace fw::app::command
