// The BQ79616's own VC open-wire check (drivers/bq79616/open_wire.hpp) against the chain emulator's model of
// the diagnostic (bsp/host/emul/bq79616/open_wire.cpp): an open wire at the bottom tap (VC0), a middle tap
// and the top tap, on a 2-device chain and a 16-device chain, found by the device's comparison alone (every
// cell keeps reading a plausible 3.7 V, which no reading rule can flag); the sinks are off at the end
// whatever happened; the latch is cleared so a repaired wire is seen; the check's time stays within its
// bound.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "chain_rig.hpp"
#include "drivers/bq79616/open_wire.hpp"
#include "regmap/bq79616.hpp"

namespace {

using namespace test;
using fw::Status;
namespace r = fw::regmap::bq79616::reg;

constexpr uint16_t kFaultSummary = fw::regmap::code16(r::FaultSummary);

// The check's owner: forwards the chain's completions to the check until it ends.
struct CheckRig : ChainRig {
  explicit CheckRig(uint8_t devices, bsp::host::Bq79616ChainEmulator::Timing timing = {})
      : ChainRig(devices, configFor(devices), timing) {
    for (size_t d = 0; d < emulator.size(); ++d) {
      for (int c = 1; c <= 16; ++c)
        emulator.setCellMicrovolts(d, c, 3700000);
    }
  }
  Status run(std::vector<uint16_t>& failing) {
    failing.assign(chain.devices(), 0xFFFF);  // anything the check does not write fails the test
    Status s = check.start(failing);
    if (s != Status::Ok) return s;
    const uint64_t t0 = harness.nowUs();
    for (int frames = 0; frames < 64; ++frames) {
      const Status r = finish(Status::Ok, fw::s(1));
      if (!check.step(r)) break;
    }
    took = harness.nowUs() - t0;
    EXPECT_FALSE(check.busy());
    return check.result();
  }
  bq::OpenWireCheck check{chain};
  uint64_t took = 0;
};

struct Tap {
  const char* name;
  int pin;       // VC pin whose wire opens
  uint16_t bit;  // the cell the device reports (bit c = cell c + 1)
};
constexpr Tap kTaps[] = {{"bottom VC0", 0, 0x0001}, {"middle VC8", 8, 0x0080}, {"top VC16", 16, 0x8000}};

class Bq79616OpenWireTap : public ::testing::TestWithParam<std::tuple<int, uint8_t>> {};

TEST_P(Bq79616OpenWireTap, TheDevicesOwnCheckNamesTheCellBesideTheOpenPin) {
  const Tap tap = kTaps[std::get<0>(GetParam())];
  const uint8_t devices = std::get<1>(GetParam());
  CheckRig rig(devices);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.harness.runFor(fw::ms(50));  // the ADC settles
  // The wire opens on the top device; the readings stay plausible (the pin's capacitor holds the node).
  const size_t open = devices - 1u;
  rig.emulator.setOpenWire(open, tap.pin, true);
  ASSERT_EQ(rig.scan(), Status::Ok) << "the readings alone show nothing";
  std::vector<uint16_t> failing;
  ASSERT_EQ(rig.run(failing), Status::Ok) << tap.name;
  EXPECT_TRUE(rig.check.verdict());
  for (size_t d = 0; d < devices; ++d)
    EXPECT_EQ(failing[d], d == open ? tap.bit : 0) << tap.name << ", device " << d;
  // The sinks are off, the latch cleared; the device's result came from one comparison per device.
  for (size_t d = 0; d < devices; ++d) {
    EXPECT_FALSE(rig.emulator.owSinksOn(d)) << "device " << d;
    EXPECT_EQ(rig.emulator.reg(d, kFaultSummary), 0) << "device " << d;
  }
  EXPECT_EQ(rig.emulator.owComparisons(), devices);
  EXPECT_LE(rig.took, bq::OpenWireCheck::worstCase(devices).us);

  // The wire is repaired: the next check says so.
  rig.emulator.setOpenWire(open, tap.pin, false);
  ASSERT_EQ(rig.run(failing), Status::Ok);
  for (size_t d = 0; d < devices; ++d)
    EXPECT_EQ(failing[d], 0) << "device " << d;
}

INSTANTIATE_TEST_SUITE_P(Taps, Bq79616OpenWireTap,
                         ::testing::Combine(::testing::Values(0, 1, 2), ::testing::Values(2, 16)));

TEST(Bq79616OpenWire, AHealthyChainPassesAndTheCheckTakesWhatItShould) {
  for (uint8_t devices : {1, 2, 16, 64}) {
    CheckRig rig(devices);
    ASSERT_EQ(rig.bringUp(), Status::Ok);
    rig.harness.runFor(fw::ms(50));
    std::vector<uint16_t> failing;
    ASSERT_EQ(rig.run(failing), Status::Ok);
    for (uint16_t f : failing)
      EXPECT_EQ(f, 0);
    EXPECT_LE(rig.took, bq::OpenWireCheck::worstCase(devices).us);
    std::printf("REPORT bq79616.open_wire_check_us devices=%u measured=%llu bound=%u (virtual time)\n",
                devices, static_cast<unsigned long long>(rig.took), bq::OpenWireCheck::worstCase(devices).us);
  }
}

// A comparison that never ends: Timeout after the last poll, no verdict, and the sinks still go off.
TEST(Bq79616OpenWire, AComparisonThatNeverEndsTimesOutWithTheSinksOff) {
  bsp::host::Bq79616ChainEmulator::Timing t;
  t.owCompareUs = 1000000;
  CheckRig rig(2, t);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.harness.runFor(fw::ms(50));
  std::vector<uint16_t> failing;
  EXPECT_EQ(rig.run(failing), Status::Timeout);
  EXPECT_FALSE(rig.check.verdict());
  EXPECT_FALSE(rig.emulator.owSinksOn(0));
  EXPECT_FALSE(rig.emulator.owSinksOn(1));
  EXPECT_LE(rig.took, bq::OpenWireCheck::worstCase(2).us);
}

// The link breaks while the sinks are on: the check ends with the chain's error and no verdict. The sinks-off
// write cannot reach the device then (a broadcast write has no answer, so the host cannot tell): the sinks
// stay on until the application's next check, which follows every recovery (bq79616_app.hpp).
TEST(Bq79616OpenWire, ALinkFailureMidCheckEndsWithoutAVerdict) {
  CheckRig rig(2);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.harness.runFor(fw::ms(50));
  std::vector<uint16_t> failing(2, 0);
  ASSERT_EQ(rig.check.start(failing), Status::Ok);
  int frames = 0;
  Status r = rig.finish(Status::Ok);
  while (rig.check.step(r) && ++frames < 64) {
    if (rig.emulator.owSinksOn(1)) rig.emulator.setDisconnected(true);
    r = rig.finish(Status::Ok);
  }
  EXPECT_EQ(rig.check.result(), Status::NoResponse);
  EXPECT_FALSE(rig.check.verdict());
  EXPECT_EQ(failing, std::vector<uint16_t>(2, 0)) << "no verdict is written";
  rig.emulator.setDisconnected(false);
  EXPECT_TRUE(rig.emulator.owSinksOn(1));
  // The next check (the link is back) ends with the sinks off.
  ASSERT_EQ(rig.run(failing), Status::Ok);
  EXPECT_FALSE(rig.emulator.owSinksOn(1));
}

// Balancing during a check: the check pauses it (CB_PAUSE), so a balancing cell is no open wire, and it
// balances again afterwards. Without the pause the emulator's comparison reports the balancing cell low (a
// bleeding FET pulls its measurement down), so a check that forgot the pause fails this test.
struct BalancingRig : CheckRig {
  BalancingRig() : CheckRig(2) {
    EXPECT_EQ(bringUp(), Status::Ok);
    harness.runFor(fw::ms(50));
    const uint8_t timers[8] = {0, 0, 0, 0, 0, 0, 0, 0x02};  // CB_CELL9_CTRL: 30 s
    EXPECT_EQ(finish(chain.startWrite(bq::RequestType::SingleWrite, 1, fw::regmap::code16(r::CbCell16Ctrl),
                                      timers)),
              Status::Ok);
    const uint8_t go = 0x22;  // FLTSTOP_EN | BAL_GO, as the Balancer writes it
    EXPECT_EQ(
        finish(chain.startWrite(bq::RequestType::SingleWrite, 1, fw::regmap::code16(r::BalCtrl2), {&go, 1})),
        Status::Ok);
    EXPECT_EQ(emulator.balancingCells(1), 0x0100);
  }
  Status broadcast(uint16_t reg, uint8_t value) {
    return finish(chain.startWrite(bq::RequestType::BroadcastWrite, 0, reg, {&value, 1}));
  }
};

TEST(Bq79616OpenWire, TheCheckPausesBalancingAndResumesIt) {
  BalancingRig rig;
  std::vector<uint16_t> failing;
  ASSERT_EQ(rig.run(failing), Status::Ok);
  EXPECT_EQ(failing[1], 0) << "a balancing cell is no open wire";
  EXPECT_EQ(failing[0], 0);
  EXPECT_EQ(rig.emulator.balancingCells(1), 0x0100) << "balancing resumed";
}

TEST(Bq79616OpenWire, WithoutThePauseTheEmulatorReportsTheBalancingCellLow) {
  BalancingRig rig;
  ASSERT_EQ(rig.broadcast(fw::regmap::code16(r::DiagCompCtrl2), bq::OpenWireCheck::kThresholdCode),
            Status::Ok);
  ASSERT_EQ(rig.broadcast(fw::regmap::code16(r::DiagCompCtrl3), 0x10), Status::Ok);
  rig.harness.runFor(fw::ms(4));
  ASSERT_EQ(rig.broadcast(fw::regmap::code16(r::DiagCompCtrl3), 0x15), Status::Ok);
  rig.harness.runFor(fw::ms(5));
  EXPECT_EQ(rig.emulator.reg(1, fw::regmap::code16(r::FaultCompVcow1)), 0x01) << "cell 9";
  EXPECT_EQ(rig.emulator.reg(0, fw::regmap::code16(r::FaultCompVcow1)), 0x00);
}

}  // namespace
