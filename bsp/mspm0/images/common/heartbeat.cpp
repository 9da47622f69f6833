#include "heartbeat.hpp"

namespace image {

void Heartbeat::start(fw::sched::Scheduler& scheduler, fw::sched::TaskId id, fw::hal::DigitalOut& led,
                      fw::Duration period) {
  scheduler_ = &scheduler;
  led_ = &led;
  id_ = id;
  scheduler.addTask(id, *this, fw::ms(1), true);
  scheduler.startTimer(timer_, id, 1, period, period);
}

void Heartbeat::run(fw::sched::EventMask) {
  led_->set(!led_->level());
  emit_(beat_++);
  scheduler_->checkIn(id_);
}

void toHex(uint32_t value, uint8_t* out, uint32_t digits) {
  for (uint32_t i = digits; i-- > 0; value >>= 4)
    out[i] = static_cast<uint8_t>("0123456789ABCDEF"[value & 0xF]);
}

}  // namespace image
