// Shared fixture of the register-level tests: a fresh register model, twin chip (of the part the test names,
// the G3507 by default) and interrupt controller per test, a Notify that counts its calls, and the check that
// no peripheral model rule was broken (RegisterModel::flag, the twin's rules included).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "hal/i2c_bus.hpp"
#include "hal/notify.hpp"
#include "mmio_model.hpp"
#include "sim/sim_irq.hpp"

namespace bsp::mspm0::test {

class RegisterTest : public ::testing::Test {
 protected:
  explicit RegisterTest(twin::Part part = twin::Part::G3507) : part_(part) {}
  void SetUp() override {
    model().reset(part_);
    bsp::host::simIrq().reset();
  }

  void TearDown() override {
    for (const std::string& rule : model().violations())
      ADD_FAILURE() << "register model rule broken: " << rule;
  }

  RegisterModel& regs() { return model(); }
  twin::Mspm0& chip() { return model().chip(); }

  // The clock-low timeout the controller on I2C0 (SDA PA0 = PINCM1, SCL PA1 = PINCM2 on both parts) runs,
  // measured on the twin: the bus pulled up, a device holds SCL low, a one-byte write starts, and TIMEOUTA
  // (I2C0 RIS bit 14, hw_i2c.h) comes this long after it, one SCL period for the START included. The
  // controller is left waiting: the test ends there.
  uint64_t i2cTimeoutOnTheTwinUs(fw::hal::I2cBus& bus) {
    chip().pins().setBoardPullUp(1, true);
    chip().pins().setBoardPullUp(2, true);
    chip().pins().setExternal(2, twin::Drive::Low);
    const uint8_t byte = 0x01;
    fw::hal::I2cTransaction t{};
    t.address = 0x08;
    t.write = std::span<const uint8_t>(&byte, 1);
    EXPECT_EQ(bus.start(std::span<fw::hal::I2cTransaction>(&t, 1), {}), fw::Status::Ok);
    const uint64_t from = chip().machine().now();
    EXPECT_TRUE(regs().runUntil([this] { return (regs().peek(0x400F1030) & (1U << 14)) != 0; }, 60000));
    return (chip().machine().now() - from) / 32;
  }

  // A Notify that counts how often it ran.
  fw::hal::Notify counter(int& calls) {
    return fw::hal::Notify{[](void* c, uint32_t) { ++*static_cast<int*>(c); }, &calls, 0};
  }

 private:
  twin::Part part_;
};

}  // namespace bsp::mspm0::test
