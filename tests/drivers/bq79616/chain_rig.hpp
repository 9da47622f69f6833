// A simulated MCU with the BQ79616 chain driver on SimUart and the chain emulator behind it, for host tests.
//
// Every operation runs on the Harness's virtual clock with a virtual-time limit: finish() fails the test
// (returns Timeout) if the driver has not reported Done within the limit, so no test can hang.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bq79616/chain_emulator.hpp"
#include "drivers/bq79616/chain.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace test {

namespace bq = fw::drivers::bq79616;

inline constexpr fw::sched::TaskId kTask = 2;
inline constexpr fw::sched::EventMask kBus = 0x1;
inline constexpr fw::sched::EventMask kTimer = 0x2;
inline constexpr fw::sched::EventMask kFault = 0x4;

class DriverTask final : public fw::sched::Task {
 public:
  bq::Chain* chain = nullptr;
  int done = 0;
  std::vector<fw::sched::EventMask> events;
  void run(fw::sched::EventMask ev) override {
    events.push_back(ev);
    if (chain != nullptr && (ev & chain->events()) != 0 && chain->onEvent(ev) == fw::drivers::Progress::Done)
      ++done;
  }
};

inline bq::ChainConfig configFor(uint8_t devices) {
  bq::ChainConfig c;
  c.devices = devices;
  return c;
}

struct ChainRig {
  ChainRig(size_t emulated, bq::ChainConfig config, bsp::host::Bq79616ChainEmulator::Timing timing = {})
      : emulator(harness.clock, uart, emulated, timing),
        chain(uart, harness.clock, fw::drivers::DriverContext{harness.sched, kTask, kBus, kTimer}, config) {
    task.chain = &chain;
    harness.sched.addTask(kTask, task);
  }
  explicit ChainRig(uint8_t devices) : ChainRig(devices, configFor(devices)) {}

  // Runs a started operation to its end within `limit` of virtual time.
  fw::Status finish(fw::Status started, fw::Duration limit = fw::s(5)) {
    if (started != fw::Status::Ok) return started;
    const int before = task.done;
    const bool ended = harness.runUntil([&] { return task.done > before; }, limit);
    EXPECT_TRUE(ended) << "the driver did not finish within " << limit.us << " us of virtual time";
    EXPECT_EQ(task.done, before + 1) << "Done must be reported exactly once";
    if (!ended) return fw::Status::Timeout;
    return chain.result();
  }
  fw::Status bringUp() { return finish(chain.startBringUp()); }
  fw::Status scan() {
    records.assign(bq::kMaxDevices, bq::DeviceRecord{});
    return finish(chain.startScan(records, summary));
  }
  size_t count(const std::string& prefix) const {
    size_t n = 0;
    for (const auto& l : uart.wireLog())
      n += l.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }

  bsp::host::Harness harness;
  bsp::host::SimUart uart{harness.clock, harness.irq};
  bsp::host::Bq79616ChainEmulator emulator;
  DriverTask task;
  bq::Chain chain;
  std::vector<bq::DeviceRecord> records;
  bq::ScanSummary summary;
};

}  // namespace test
