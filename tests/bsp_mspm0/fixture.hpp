// Shared fixture of the register-level tests: a fresh register model, twin chip (of the part the test names,
// the G3507 by default) and interrupt controller per test, a Notify that counts its calls, and the check that
// no peripheral model rule was broken (RegisterModel::flag, the twin's rules included).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

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

  // A Notify that counts how often it ran.
  fw::hal::Notify counter(int& calls) {
    return fw::hal::Notify{[](void* c, uint32_t) { ++*static_cast<int*>(c); }, &calls, 0};
  }

 private:
  twin::Part part_;
};

}  // namespace bsp::mspm0::test
