// Test rig for the BQ4050 driver: one simulated MCU (Harness), the SMBus at 100 kHz with the image's 25 ms
// stretch limit, the gauge emulator at 0x0B and the driver owned by a task, plus the independent CRC-8 the
// tests check PECs with.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

#include "bq4050/gauge_emulator.hpp"
#include "drivers/bq4050/gauge.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"

namespace bq4050_test {

namespace bq = fw::drivers::bq4050;
using Emu = bsp::host::Bq4050Emulator;
using fw::Status;

constexpr fw::sched::TaskId kTask = 1;
constexpr fw::sched::EventMask kBus = 0x1;
constexpr fw::sched::EventMask kTimer = 0x2;

// CRC-8, polynomial x^8 + x^2 + x + 1, init 0, MSB first: written out bit by bit from the definition
// (SMBus 2.0 5.4.1.2), sharing nothing with fw::crc or the emulator's table.
inline uint8_t referenceCrc8(const std::vector<uint8_t>& bytes) {
  unsigned crc = 0;
  for (uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = (crc & 0x80) ? ((crc << 1) ^ 0x07) & 0xFF : (crc << 1) & 0xFF;
  }
  return static_cast<uint8_t>(crc);
}
inline uint8_t referenceCrc8(std::initializer_list<uint8_t> bytes) {
  return referenceCrc8(std::vector<uint8_t>(bytes));
}

inline std::string hex(std::initializer_list<uint8_t> bytes) {
  std::string s;
  char buf[4];
  for (uint8_t b : bytes) {
    std::snprintf(buf, sizeof buf, "%s%02X", s.empty() ? "" : " ", b);
    s += buf;
  }
  return s;
}

class DriverTask final : public fw::sched::Task {
 public:
  bq::Gauge* gauge = nullptr;
  int done = 0;
  void run(fw::sched::EventMask events) override {
    if (gauge != nullptr && (events & gauge->events()) != 0 &&
        gauge->onEvent(events) == fw::drivers::Progress::Done)
      ++done;
  }
};

inline bq::GaugeConfig config(bq::PecMode pec) {
  bq::GaugeConfig c;
  c.pec = pec;
  return c;
}

struct Rig {
  explicit Rig(bq::GaugeConfig cfg = config(bq::PecMode::On), uint32_t bitRate = 100000)
      : bus(harness.clock, harness.irq, {bitRate, fw::ms(25), fw::us(4)}),
        gauge(bus, harness.clock, fw::drivers::DriverContext{harness.sched, kTask, kBus, kTimer}, cfg) {
    bus.attach(Emu::kAddress, emu);
    task.gauge = &gauge;
    harness.sched.addTask(kTask, task);
  }

  // Runs one started operation to its end (every operation is bounded well inside 10 s of virtual time).
  Status finish(Status started) {
    if (started != Status::Ok) return started;
    const int before = task.done;
    harness.runUntil([&] { return task.done > before; }, fw::s(10));
    EXPECT_EQ(task.done, before + 1) << "the operation must end exactly once";
    return gauge.result();
  }

  Status readWord(uint8_t cmd, uint16_t& out) { return finish(gauge.startReadWord(cmd, out)); }
  Status scan(bq::Measurement& m) { return finish(gauge.startScan(m)); }

  std::vector<std::string> wire() const {
    std::vector<std::string> v;
    for (const auto& r : bus.wireLog())
      v.push_back(r.text);
    return v;
  }
  void clearWire() { bus.clearWireLog(); }

  bsp::host::Harness harness;
  bsp::host::SimI2cBus bus;
  Emu emu;
  DriverTask task;
  bq::Gauge gauge;
};

}  // namespace bq4050_test
