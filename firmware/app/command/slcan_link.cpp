#include "app/command/slcan_link.hpp"

#include "app/command/identity.hpp"
#include "app/publish/slcan.hpp"
#include "app/publish/slcan_publisher.hpp"

namespace fw::app::command {

bool SlcanLink::step(CommandHandler& handler, sched::Scheduler& s) {
  uint8_t byte;
  bool any = false;
  while (rx_.read(byte)) {
    any = true;
    const uint32_t lost = rx_.lost();
    const SlcanAdapter::Info info{
        static_cast<uint8_t>(kFirmwareIdentity.major * 10 + kFirmwareIdentity.minor), serial_,
        lost != lostAtLastF_};
    SlcanAdapter::Line line;
    if (!adapter_.feed(byte, info, line)) continue;
    if (line.answer[0] == 'F') lostAtLastF_ = lost;  // the flags were read: overrun is cleared
    Replies r{};
    if (line.hasFrame) handler.handle(line.frame, r);
    send(line.answer, line.answerLength, r, s);
    return true;
  }
  return any;
}

void SlcanLink::send(const uint8_t* answer, uint8_t length, const Replies& r, sched::Scheduler& s) {
  uint8_t n = 0;
  for (uint8_t i = 0; i < length; ++i)
    outbox_.text[n++] = answer[i];
  for (uint8_t k = 0; k < r.count; ++k)
    n = static_cast<uint8_t>(
        n + app::slcan::encode(r.frame[k], {outbox_.text + n, static_cast<size_t>(SlcanOutbox::kBytes - n)}));
  if (n == 0) return;
  outbox_.length = n;
  s.post(kPublisherTask, SlcanPublisher::kReply);
}

}  // namespace fw::app::command
