// An I2C/SMBus target that answers with fuzz bytes, and the task that forwards a driver's events: what the
// BQ769x2 and BQ4050 fuzz targets put behind the host BSP's simulated bus (bsp/host/sim/i2c_bus.hpp) so the
// drivers' response checks see any byte sequence a broken or hostile device could send.
//
// Every byte the controller clocks out is the next input byte. Faults come from the input too: when the
// input's fault flags allow it, a START or written byte is refused (NACK) when its fault byte is 0xEE, and a
// byte is stretched by (fault byte) x 100 us, beyond the bus's stretch limit for the highest values.
#pragma once

#include <cstdint>

#include "fuzz_input.hpp"
#include "sched/scheduler.hpp"
#include "sim/i2c_target.hpp"

namespace bms_fuzz {

class FuzzI2cTarget final : public bsp::host::I2cTarget {
 public:
  FuzzI2cTarget(Input& in, bool nacks, bool stretches) : in_(in), nacks_(nacks), stretches_(stretches) {}

  bsp::host::I2cReply onStart(bool) override { return reply(); }
  bsp::host::I2cReply onWrite(uint8_t) override { return reply(); }
  uint8_t onRead(fw::Duration& stretch) override {
    stretch = stretches_ ? fw::us(100 * in_.byte()) : fw::Duration{};
    return in_.empty() ? 0xFF : in_.byte();  // an idle bus reads high
  }
  void onStop() override {}

 private:
  bsp::host::I2cReply reply() {
    bsp::host::I2cReply r;
    if (nacks_) r.ack = in_.byte() != 0xEE;
    if (stretches_) r.stretch = fw::us(100 * in_.byte());
    return r;
  }

  Input& in_;
  bool nacks_;
  bool stretches_;
};

// Forwards a driver's events to it and counts the operations that reported Done.
template <class Driver>
class DriverTask final : public fw::sched::Task {
 public:
  explicit DriverTask(Driver& driver) : driver_(driver) {}
  void run(fw::sched::EventMask events) override {
    if ((events & driver_.events()) != 0 && driver_.onEvent(events) == fw::drivers::Progress::Done) ++done;
  }
  int done = 0;

 private:
  Driver& driver_;
};

}  // namespace bms_fuzz
