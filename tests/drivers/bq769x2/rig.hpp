// A simulated MCU running the BQ769x2/BQ7690x driver on a SimI2cBus, with the device emulator behind it.
//
// Every operation runs on the Harness's virtual clock with a virtual-time limit: finish() fails the test
// (and returns Timeout) if the driver has not reported Done within the limit, so no test can hang, and it
// checks that Done came exactly once.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bq769x2/emulator.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"

namespace test769 {

namespace drv = fw::drivers::bq769x2;
using Emu = bsp::host::Bq769xEmulator;
using fw::Status;

inline constexpr fw::sched::TaskId kTask = 2;
inline constexpr fw::sched::EventMask kBus = 0x1;
inline constexpr fw::sched::EventMask kTimer = 0x2;

// The driver's task: forwards the driver's events and counts finished operations (monitor operations and
// raw link operations started while the monitor is idle).
class DriverTask final : public fw::sched::Task {
 public:
  drv::Monitor* monitor = nullptr;
  int done = 0;
  void run(fw::sched::EventMask ev) override {
    if (monitor == nullptr || (ev & monitor->events()) == 0) return;
    const bool linkBusy = monitor->link().busy();
    const bool monitorBusy = monitor->busy();
    if (monitor->onEvent(ev) == fw::drivers::Progress::Done ||
        (!monitorBusy && linkBusy && !monitor->link().busy()))
      ++done;
  }
};

inline drv::MonitorConfig crcConfig(bool crc) {
  drv::MonitorConfig c;
  c.link.crc = crc;
  return c;
}

template <class Front>
struct RigT {
  RigT(Emu::Model model, drv::MonitorConfig config, Emu::Timing timing, bsp::host::SimI2cConfig busConfig)
      : bus(harness.clock, harness.irq, busConfig),
        emu(harness.clock, model, timing),
        driver(makeDriver(model, config)) {
    bus.attach(0x08, emu);
    task.monitor = &driver;
    harness.sched.addTask(kTask, task);
  }

  Front makeDriver(Emu::Model model, const drv::MonitorConfig& config) {
    const fw::drivers::DriverContext ctx{harness.sched, kTask, kBus, kTimer};
    if constexpr (std::is_same_v<Front, drv::Bq769x2>) {
      (void)model;
      return Front(bus, harness.clock, ctx, config);
    } else {
      return Front(bus, harness.clock, ctx, model == Emu::Model::Bq76905 ? drv::kBq76905 : drv::kBq76907,
                   config);
    }
  }

  // Runs a started operation to its end within `limit` of virtual time.
  Status finish(Status started, fw::Duration limit = fw::s(1)) {
    if (started != Status::Ok) return started;
    const int before = task.done;
    const bool ended = harness.runUntil([&] { return task.done > before; }, limit);
    EXPECT_TRUE(ended) << "the driver did not finish within " << limit.us << " us of virtual time";
    EXPECT_EQ(task.done, before + 1) << "Done must be reported exactly once";
    if (!ended) return Status::Timeout;
    return driver.busy() ? Status::Timeout : (startedOnLink ? driver.link().result() : driver.result());
  }
  // Monitor operations.
  Status run(Status started, fw::Duration limit = fw::s(1)) {
    startedOnLink = false;
    return finish(started, limit);
  }
  // Raw link operations.
  Status runLink(Status started, fw::Duration limit = fw::s(1)) {
    startedOnLink = true;
    const Status s = finish(started, limit);
    startedOnLink = false;
    return s;
  }

  std::vector<std::string> wire() const {
    std::vector<std::string> lines;
    for (const auto& r : bus.wireLog())
      lines.push_back(r.text);
    return lines;
  }
  std::string wireText() const {
    std::string all;
    for (const auto& r : bus.wireLog())
      all += r.text + "\n";
    return all;
  }
  bool sawLine(const std::string& line) const {
    for (const auto& r : bus.wireLog())
      if (r.text == line) return true;
    return false;
  }
  size_t count(const std::string& prefix) const {
    size_t n = 0;
    for (const auto& r : bus.wireLog())
      n += r.text.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }
  void clearWire() { bus.clearWireLog(); }

  bsp::host::Harness harness;
  bsp::host::SimI2cBus bus;
  Emu emu;
  DriverTask task;
  Front driver;
  bool startedOnLink = false;
};

inline bsp::host::SimI2cConfig fastBus() {
  return {400000, fw::ms(20), fw::us(4)};
}

struct Rig : RigT<drv::Bq769x2> {
  explicit Rig(drv::MonitorConfig config = {}, Emu::Timing timing = {},
               bsp::host::SimI2cConfig busConfig = fastBus())
      : RigT(Emu::Model::Bq76952, config, timing, busConfig) {}
  Status scan(drv::Bq769x2Measurement& m, fw::Duration limit = fw::s(1)) {
    return run(driver.startScan(m), limit);
  }
};

struct Rig7690x : RigT<drv::Bq7690x> {
  explicit Rig7690x(Emu::Model model = Emu::Model::Bq76907, drv::MonitorConfig config = {},
                    Emu::Timing timing = {})
      : RigT(model, config, timing, fastBus()) {}
  Status scan(drv::Bq7690xMeasurement& m, fw::Duration limit = fw::s(1)) {
    return run(driver.startScan(m), limit);
  }
};

// The emulator alone on a bus, driven by raw transactions (no driver).
struct Raw {
  bsp::host::Harness h;
  bsp::host::SimI2cBus bus{h.clock, h.irq, {400000, fw::ms(20), fw::us(4)}};
  Emu emu;
  bool done = false;
  explicit Raw(Emu::Model model = Emu::Model::Bq76952) : emu(h.clock, model) { bus.attach(0x08, emu); }
  Status run(std::vector<fw::hal::I2cTransaction> list) {
    done = false;
    const Status s =
        bus.start(list, fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done});
    if (s != Status::Ok) return s;
    h.runUntil([&] { return done; }, fw::ms(50));
    return list.back().status;
  }
  Status write(std::vector<uint8_t> bytes) { return run({{0x08, bytes, {}}}); }
  std::vector<uint8_t> read(uint8_t cmd, size_t n) {
    std::vector<uint8_t> rx(n);
    EXPECT_EQ(run({{0x08, {&cmd, 1}, rx}}), Status::Ok);
    return rx;
  }
  std::string last() const { return bus.wireLog().back().text; }
};

}  // namespace test769
