// ChipRig: one MSPM0 twin running a two-instruction loop, for tests that drive a peripheral's registers
// through the address map as the CPU's loads and stores would, while the loop lets time pass.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "mspm0.hpp"

namespace twin_test {

class ChipRig : public ::testing::Test {
 protected:
  // `loop`: two Thumb instructions, as bytes, that loop (the second a `B .-2`). The vector table puts SP at
  // the top of SRAM and the reset entry at the loop: at 0x100 in flash, or, with `fromSram`, at the bottom
  // of SRAM, where it is copied after power-on.
  ChipRig(twin::Part part, std::array<uint8_t, 4> loop, bool fromSram = false) : chip_(part) {
    const uint32_t sramBase = part == twin::Part::G3507 ? 0x20200000 : 0x20000000;
    const uint32_t sp = sramBase + (part == twin::Part::G3507 ? 0x8000 : 0x1000);
    const uint32_t entry = (fromSram ? sramBase : 0x100) | 1;
    std::vector<uint8_t> flash(0x104, 0);
    for (int i = 0; i < 4; ++i) {
      flash[i] = static_cast<uint8_t>(sp >> (8 * i));
      flash[4 + i] = static_cast<uint8_t>(entry >> (8 * i));
      flash[0x100 + i] = loop[i];
    }
    chip_.machine().loadFlash(flash);
    chip_.machine().powerOn();
    if (fromSram) {
      for (uint32_t i = 0; i < 4; ++i)
        chip_.machine().busWrite(sramBase + i, 1, loop[i]);
    }
  }

  uint32_t rd(uint32_t address) {
    uint32_t v = 0;
    EXPECT_TRUE(chip_.machine().map().load(address, 4, v)) << std::hex << address;
    return v;
  }
  void wr(uint32_t address, uint32_t value) {
    EXPECT_TRUE(chip_.machine().map().store(address, 4, value)) << std::hex << address;
  }
  void runUs(uint64_t us) { chip_.machine().run(chip_.machine().now() + us * 32); }
  bool stopped() { return chip_.machine().stopped(); }
  std::string why() { return chip_.machine().stopReason(); }

  twin::Mspm0 chip_;
};

}  // namespace twin_test
