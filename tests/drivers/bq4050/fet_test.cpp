// FET control through MAC toggles: read, toggle one bit, read back, until the gauge's state is the request;
// then OperationStatus tells what the FETs actually do.
#include <gtest/gtest.h>

#include <algorithm>

#include "rig.hpp"

namespace bq4050_test {
namespace {

using K = Emu::FaultKind;
constexpr uint16_t kFetEn = 0x0010;
constexpr uint16_t kGaugeEn = 0x0008;

std::vector<uint16_t> toggles(const Emu& emu) {
  std::vector<uint16_t> v;
  for (uint16_t s : emu.macLog()) {
    if (s == 0x0022 || s == 0x001E || s == 0x001F || s == 0x0020) v.push_back(s);
  }
  return v;
}

TEST(Bq4050Fet, FirmwareControlIsRestoredOnAGaugeLeftInTestMode) {
  // TI E2E 969210: FETs that stay off because FET_EN = 0. One FETControl toggle gives them back to the gauge.
  Rig rig;
  rig.emu.setManufacturingStatus(kGaugeEn);  // FET_EN = 0, no test FET on
  ASSERT_FALSE(rig.emu.dsgFet());
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::firmware(), state)), Status::Ok);
  EXPECT_TRUE(state.firmwareControl());
  EXPECT_TRUE(state.chg());
  EXPECT_TRUE(state.dsg());
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x0022}));
  const auto w = rig.wire();
  EXPECT_NE(
      std::find(w.begin(), w.end(), "S 16 00 22 00 " + hex({referenceCrc8({0x16, 0x00, 0x22, 0x00})}) + " P"),
      w.end());
}

TEST(Bq4050Fet, AlreadyInTheRequestedStateSendsNoToggle) {
  Rig rig;
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::firmware(), state)), Status::Ok);
  EXPECT_TRUE(toggles(rig.emu).empty());
  EXPECT_EQ(rig.wire().size(), 4u) << "ManufacturingStatus and OperationStatus, two transactions each";
}

TEST(Bq4050Fet, AllOffLeavesFirmwareControlAndOpensBothFets) {
  Rig rig;
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::allOff(), state)), Status::Ok);
  EXPECT_FALSE(state.firmwareControl());
  EXPECT_FALSE(state.chg());
  EXPECT_FALSE(state.dsg());
  EXPECT_FALSE(rig.emu.chgFet());
  EXPECT_FALSE(rig.emu.dsgFet());
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x0022}));
}

TEST(Bq4050Fet, ManualOnTurnsDsgOnBeforeChg) {
  // TI E2E 1445117: above 16 V with DSG off, the CHG FET does not follow its toggle. DSG first avoids it.
  Rig rig;
  rig.emu.setVoltage(16800);
  rig.emu.setManufacturingStatus(kGaugeEn);
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::manual(true, true), state)), Status::Ok);
  EXPECT_TRUE(state.chg());
  EXPECT_TRUE(state.dsg());
  EXPECT_FALSE(state.pchg());
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x0020, 0x001F}));
}

TEST(Bq4050Fet, ManualOffTurnsChgOffBeforeDsg) {
  Rig rig;
  rig.emu.setManufacturingStatus(kGaugeEn | 0x0007);  // test mode, all three test FETs on
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::manual(false, true), state)), Status::Ok);
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x001F, 0x001E}));
  EXPECT_FALSE(state.chg());
  EXPECT_TRUE(state.dsg());
  EXPECT_FALSE(state.pchg());
}

TEST(Bq4050Fet, ChgFlagWithoutTheFetIsReportedNotBelieved) {
  Rig rig;
  rig.emu.setVoltage(16800);
  rig.emu.setManufacturingStatus(kGaugeEn);
  bq::FetState state;
  EXPECT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::manual(true, false), state)),
            Status::VerifyFailed);
  EXPECT_EQ(rig.emu.manufacturingStatus() & 0x0002, 0x0002) << "the flag says CHG on";
  EXPECT_FALSE(rig.emu.chgFet()) << "the FET is off";
}

TEST(Bq4050Fet, SealedGaugeIgnoresTheToggleOnce) {
  Rig rig;
  rig.emu.setSealed(true);
  bq::FetState state;
  EXPECT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::allOff(), state)), Status::VerifyFailed);
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x0022})) << "one ignored toggle is enough to tell";
  EXPECT_EQ(rig.emu.manufacturingStatus() & kFetEn, kFetEn);
}

TEST(Bq4050Fet, FailedToggleIsNotBlindlyResentButDecidedByTheStateReadBack) {
  Rig rig;
  rig.emu.inject({.kind = K::DataNack, .command = 0x00, .index = 2});  // the toggle's high byte refused
  bq::FetState state;
  ASSERT_EQ(rig.finish(rig.gauge.startFetControl(bq::FetRequest::allOff(), state)), Status::Ok);
  EXPECT_EQ(toggles(rig.emu), (std::vector<uint16_t>{0x0022})) << "executed exactly once";
  EXPECT_FALSE(state.firmwareControl());
  EXPECT_EQ(rig.gauge.stats().count(Status::DataNack), 1u);
  // The refused toggle was followed by a fresh ManufacturingStatus read, not by an immediate resend.
  const auto w = rig.wire();
  size_t refused = 0;
  while (refused < w.size() && w[refused].find("NACK") == std::string::npos)
    ++refused;
  ASSERT_LT(refused + 1, w.size());
  EXPECT_EQ(w[refused + 1].rfind("S 16 44 02 57 00", 0), 0u) << w[refused + 1];
}

TEST(Bq4050Fet, GaugeGoneDuringTheToggleEndsWithNack) {
  Rig rig;
  rig.emu.setManufacturingStatus(kGaugeEn);
  bq::FetState state;
  ASSERT_EQ(rig.gauge.startFetControl(bq::FetRequest::firmware(), state), Status::Ok);
  // Let the ManufacturingStatus read finish, then take the gauge off the bus.
  rig.harness.runUntil([&] { return rig.bus.wireLog().size() >= 2; }, fw::s(1));
  rig.bus.detach(Emu::kAddress);
  EXPECT_EQ(rig.finish(Status::Ok), Status::Nack);
}

}  // namespace
}  // namespace bq4050_test
