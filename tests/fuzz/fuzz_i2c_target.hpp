// An I2C/SMBus target that answers with fuzz bytes, the task that forwards a driver's events and the bench
// that runs a driver's operations: what the BQ769x2 and BQ4050 fuzz targets put behind the host BSP's
// simulated bus (bsp/host/sim/i2c_bus.hpp) so the drivers' response checks see any byte sequence a broken or
// hostile device could send.
//
// Every byte the controller clocks out is the next input byte. Faults come from the input too: when the
// input's fault flags allow it, a START or written byte is refused (NACK) when its fault byte is 0xEE, and a
// byte is stretched by (fault byte) x 100 us, beyond the bus's stretch limit for the highest values.
#pragma once

#include <cstdint>

#include "drivers/operation.hpp"
#include "fuzz_input.hpp"
#include "sched/scheduler.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"
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

// One simulated MCU (bsp/host/sim/harness.hpp) with the fuzz device at `address` on its bus. The input's
// flags byte: bit 0 allows NACKs, bit 1 clock stretches.
struct Bench {
  static constexpr fw::sched::TaskId kTask = 1;
  static constexpr fw::sched::EventMask kBus = 0x1, kTimer = 0x2;

  Bench(Input& in, uint8_t flags, uint8_t address, bsp::host::SimI2cConfig config = {})
      : bus(harness.clock, harness.irq, config), device(in, (flags & 1) != 0, (flags & 2) != 0) {
    bus.attach(address, device);
  }
  fw::drivers::DriverContext context() { return {harness.sched, kTask, kBus, kTimer}; }

  // Runs an operation the driver started to its end: Done exactly once within `limit` of virtual time, then
  // the driver idle within `settle` (a bus transaction that outlived a driver's guard completes); anything
  // else is a finding.
  template <class Driver>
  void finish(Driver& driver, DriverTask<Driver>& task, fw::Duration limit, fw::Duration settle = {}) {
    const int before = task.done;
    const bool ended = harness.runUntil([&] { return task.done > before; }, limit);
    const bool idle = harness.runUntil([&] { return !driver.busy(); }, settle);
    if (!ended || !idle || task.done != before + 1) __builtin_trap();
  }

  bsp::host::Harness harness;
  bsp::host::SimI2cBus bus;
  FuzzI2cTarget device;
};

}  // namespace bms_fuzz
