// The BQ76952 emulator's detached sense wire and the device's own cell open-wire check (SLUUBY2B "Cell Open
// Wire", Settings:Cell Open-Wire:Check Time; bsp/host/emul/bq769x2/open_wire.cpp), read back over the bus as
// the host reads cells: without the check the detached input keeps its voltage and nothing is seen; with it,
// each check drains the node, the cell below the input reads low and the one above it high, and the device's
// CUV / COV trip. A test per tap position: VC0 (no sink: unseen, and read true), VC1 (the lowest sink), a
// middle one and the top.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;

struct Device : Raw {
  explicit Device(uint8_t checkTimeS) {
    EXPECT_EQ(write({0x3E, 0x9A, 0x00}), Status::Ok);  // SLEEP_DISABLE: a reading every scan
    h.runFor(fw::ms(1));
    emu.setAllCellsMv(3700);
    emu.setDataMemory(map::dm::EnabledProtectionsA.address, 0xBC, 1);  // COV and CUV among them
    emu.setDataMemory(map::dm::CheckTime.address, checkTimeS, 1);
  }
  int cellMv(int cell) {
    const auto rx = read(static_cast<uint8_t>(0x14 + 2 * (cell - 1)), 2);
    return static_cast<int16_t>(rx[0] | rx[1] << 8);
  }
  bool cuv() { return (emu.safetyStatusA() & map::bits::SafetyA::cuv_mask) != 0; }
  bool cov() { return (emu.safetyStatusA() & map::bits::SafetyA::cov_mask) != 0; }
};

// SLUUBY2B: Check Time defaults to 5 s, so a device left alone checks; one that shipped with 0 does not.
TEST(Bq769x2OpenWire, TheCheckIsOnByDefaultEveryFiveSeconds) {
  Raw fresh;
  EXPECT_EQ(fresh.emu.dataMemory(map::dm::CheckTime.address, 1), 5u);
}

// Check Time 0: the node holds what it had; the readings, and the device, see nothing for as long as we look.
TEST(Bq769x2OpenWire, WithoutTheCheckAnOpenInputIsNotSeen) {
  Device d(0);
  d.emu.setOpenWire(8, true);
  d.h.runFor(fw::s(30));
  EXPECT_EQ(d.cellMv(8), 3700);
  EXPECT_EQ(d.cellMv(9), 3700);
  EXPECT_FALSE(d.cuv() || d.cov());
  // A cell below the open input that changes still shows; the one above it moves the other way (it is the
  // difference to the held node).
  d.emu.setCellMv(8, 3600);
  d.h.runFor(fw::ms(10));
  EXPECT_EQ(d.cellMv(8), 3700) << "cell 8's top is the held node";
  EXPECT_EQ(d.cellMv(9), 3600);
}

class Tap : public ::testing::TestWithParam<int> {};

// Check Time 1 s, 55 uA for 3 ms on the assumed 100 nF: 1650 mV per check, down to the input below.
TEST_P(Tap, EachCheckDrainsTheNodeTheCellBelowReadsLowTheOneAboveHigh) {
  const int pin = GetParam();
  Device d(1);
  d.h.runFor(fw::ms(100));
  d.emu.setOpenWire(pin, true);
  d.h.runFor(fw::ms(800));
  EXPECT_EQ(d.cellMv(pin), 3700) << "no check yet: the node holds";
  d.h.runFor(fw::ms(200));  // the check at 1 s
  EXPECT_EQ(d.cellMv(pin), 3700 - 1650);
  if (pin < 16) {
    EXPECT_EQ(d.cellMv(pin + 1), 3700 + 1650);
  }
  d.h.runFor(fw::s(1));
  EXPECT_EQ(d.cellMv(pin), 3700 - 3300);
  if (pin < 16) {
    EXPECT_EQ(d.cellMv(pin + 1), 3700 + 3300);
  }
  d.h.runFor(fw::s(1));
  EXPECT_EQ(d.cellMv(pin), 0) << "at the input below";
  if (pin < 16) {
    EXPECT_EQ(d.cellMv(pin + 1), 7400) << "both cells";
  }
  d.h.runFor(fw::s(1));
  EXPECT_EQ(d.cellMv(pin), 0) << "it goes no lower";
  EXPECT_TRUE(d.cuv()) << "SLUUBY2B: Cell Undervoltage on that cell";
  if (pin < 16) {
    EXPECT_TRUE(d.cov()) << "and Cell Overvoltage on the cell above";
  }
  // Connected again: the readings are true at once.
  d.emu.setOpenWire(pin, false);
  d.h.runFor(fw::ms(10));
  EXPECT_EQ(d.cellMv(pin), 3700);
  if (pin < 16) {
    EXPECT_EQ(d.cellMv(pin + 1), 3700);
  }
}

INSTANTIATE_TEST_SUITE_P(Bq769x2OpenWire, Tap, ::testing::Values(1, 8, 16),
                         [](const ::testing::TestParamInfo<int>& i) {
                           return "VC" + std::to_string(i.param);
                         });

// VC0 has no sink (the BQ76922 data sheet lists I(OW) for VC1 and up): a detached VC0 holds VSS's potential,
// cell 1 reads true and the device sees nothing (regmaps/README.md, open questions).
TEST(Bq769x2OpenWire, AnOpenVc0IsNotSeenAndCell1ReadsTrue) {
  Device d(1);
  d.emu.setOpenWire(0, true);
  d.h.runFor(fw::s(10));
  EXPECT_EQ(d.cellMv(1), 3700);
  EXPECT_FALSE(d.cuv() || d.cov());
}

// The device reads Check Time at each interval: with the default 5 s the first drain comes at 5 s.
TEST(Bq769x2OpenWire, TheIntervalIsCheckTime) {
  Device d(5);
  d.h.runFor(fw::ms(100));
  d.emu.setOpenWire(4, true);
  d.h.runFor(fw::ms(4800));
  EXPECT_EQ(d.cellMv(4), 3700);
  d.h.runFor(fw::ms(200));
  EXPECT_EQ(d.cellMv(4), 3700 - 1650);
}

}  // namespace
