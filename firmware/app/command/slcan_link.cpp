#include "app/command/slcan_link.hpp"

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
  uint8_t n = 0;
  for (uint8_t i = 0; i < length; ++i)
    outbox_.text[n++] = answer[i];
  for (uint8_t k = 0; k < r.count; ++k) {
    app::slcan::encodeStandard(static_cast<uint16_t>(r.frame[k].id), r.frame[k].data, outbox_.text + n);
    n = static_cast<uint8_t>(n + app::slcan::kStandardLength);
  }
  if (n == 0) return;
  outbox_.length = n;
  s.post(kPublisherTask, SlcanPublisher::kReply);
}

}  // namespace fw::app::command
