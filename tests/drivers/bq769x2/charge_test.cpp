// The accumulated charge (issue 29): the emulators count the current into DASTATUS6 / PASSQ as the devices
// do (units, the counter's width and wrap, RESET_PASSQ and a device reset); one scan asks for it and the next
// reads it with its echo, so each BQ76952 scan stays within its budget of 6 transactions and 3 ms
// (scan_test.cpp measures it).
#include <gtest/gtest.h>

#include "core/bytes.hpp"
#include "rig.hpp"

namespace {

using namespace test769;
namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;

struct Rig7 : RigT<drv::Bq7690x> {
  Rig7() : RigT(Emu::Model::Bq76907, {}, {}, fastBus()) {}
  Status scan(drv::Bq7690xMeasurement& m) { return run(driver.startScan(m)); }
};

// A request scan and the read scan after it: the second's charge.
template <class R, class M>
Status chargeScans(R& r, M& m) {
  const Status first = r.scan(m);
  if (first != Status::Ok) return first;
  EXPECT_FALSE(m.charge.valid) << "a request scan carries no charge";
  return r.scan(m);
}

int64_t bq769x2Count(const drv::ChargeCounter& c) {
  return static_cast<int64_t>((static_cast<uint64_t>(fw::bytes::loadLe32(c.raw)) << 32) |
                              fw::bytes::loadLe32(c.raw + 4));
}

// SLUUBY2B DASTATUS6 / E2E 970294: integer userAh, fraction in 1/2^32 userAh, time in s; after a clear the
// fraction reads 0x7FFFFFFF.
TEST(Bq769x2Charge, DastatusSixCountsTheCurrentInUserAmpHoursAndSeconds) {
  Rig r;
  r.emu.setCurrentMa(0);
  drv::Bq769x2Measurement m;
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  ASSERT_TRUE(m.charge.valid);
  const int64_t start = bq769x2Count(m.charge);
  r.emu.setCurrentMa(-3600);  // 3.6 A for 10 s: 10 mAh out
  r.harness.runFor(fw::s(10));
  r.emu.setCurrentMa(0);
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  ASSERT_TRUE(m.charge.valid);
  const int64_t delta = bq769x2Count(m.charge) - start;
  EXPECT_EQ(delta, -(int64_t{10} << 32)) << "10 userAh of 1 mA out";
  EXPECT_EQ(bq769x2Count(m.charge), r.emu.chargeCount());
  EXPECT_GE(fw::bytes::loadLe32(m.charge.raw + 8), 10u) << "accumulated time in s";
}

TEST(Bq769x2Charge, ResetPassqAndADeviceResetClearTheCounterToHalfAUserAmpHour) {
  Rig r;
  r.emu.setCurrentMa(5000);
  r.harness.runFor(fw::s(2));
  r.emu.setCurrentMa(0);
  EXPECT_NE(r.emu.chargeCount(), 0x7FFFFFFF);
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(m2::sub::ResetPassq.address)), Status::Ok);
  EXPECT_EQ(r.emu.chargeCount(), 0x7FFFFFFF);
  r.emu.setCurrentMa(1000);
  r.harness.runFor(fw::s(36));  // 10 mAh
  r.emu.reset();
  EXPECT_EQ(r.emu.chargeCount(), 0x7FFFFFFF);
}

// The integer part is a signed 32-bit userAh count: past 2^31 - 1 it wraps to -2^31 (a fixed-width
// register); the firmware's difference of two readings stays right across it (app soc tests).
TEST(Bq769x2Charge, TheCountWrapsAtItsThirtyTwoBitIntegerPart) {
  Rig r;
  r.emu.setCurrentMa(0);
  r.emu.presetChargeCount(static_cast<int64_t>(0x7FFFFFFFULL << 32));  // 2^31 - 1 userAh
  r.emu.setCurrentMa(36000);
  r.harness.runFor(fw::s(1));  // +10 mAh
  r.emu.setCurrentMa(0);
  EXPECT_EQ(static_cast<uint64_t>(r.emu.chargeCount()), (0x80000009ULL << 32)) << "wrapped to -2^31 + 9";
}

// USER_AMPS = 10 mA: the same 36 A for a second is 1 userAh (SLUUBY2B DA Configuration).
TEST(Bq769x2Charge, TheCountFollowsTheUserAmpsUnit) {
  Rig r;
  r.emu.setCurrentMa(0);
  r.emu.setDataMemory(m2::dm::DaConfiguration.address, 0x06, 1);
  const int64_t start = r.emu.chargeCount();
  r.emu.setCurrentMa(36000);
  r.harness.runFor(fw::s(1));
  r.emu.setCurrentMa(0);
  EXPECT_EQ(r.emu.chargeCount() - start, int64_t{1} << 32);
}

// A device still computing the result answers FF FF at 0x3E: the scan's other values stand, the charge is
// not taken. (Scans here run back to back; the images' scans are 100 ms apart.)
TEST(Bq769x2Charge, AResultNotReadyInTimeLeavesTheChargeOutOfThatScan) {
  Rig r;
  r.emu.setLatency(m2::sub::Dastatus6.address, fw::ms(20));
  drv::Bq769x2Measurement m;
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  EXPECT_FALSE(m.charge.valid);
  EXPECT_EQ(m.reg.cellMv[0], 3700);
  r.emu.setLatency(m2::sub::Dastatus6.address, {});
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  EXPECT_TRUE(m.charge.valid);
}

// A command written between the request and the read (here a FET subcommand) takes the subcommand window:
// its echo names it, so the read scan leaves the charge out instead of taking that command's bytes.
TEST(Bq769x2Charge, ACommandBetweenTheRequestAndTheReadLeavesTheChargeOut) {
  Rig r;
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOff)), Status::Ok);
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_FALSE(m.charge.valid);
  EXPECT_EQ(m.reg.cellMv[0], 3700);
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  EXPECT_TRUE(m.charge.valid) << "asked for again";
}

// SLUUCJ0 PASSQ: a signed 48-bit count of userA-seconds (low 32 bits, then the high 16 sign-extended), time
// in 250 ms.
TEST(Bq7690xCharge, PassqCountsUserAmpSecondsInFortyEightBits) {
  Rig7 r;
  r.emu.setCurrentMa(0);
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  ASSERT_TRUE(m.charge.valid);
  EXPECT_EQ(fw::bytes::loadLe32(m.charge.raw), 0u);
  r.emu.setCurrentMa(-2000);
  r.harness.runFor(fw::s(5));  // -10 A-s: -10000 mA-s
  r.emu.setCurrentMa(0);
  ASSERT_EQ(chargeScans(r, m), Status::Ok);
  ASSERT_TRUE(m.charge.valid);
  EXPECT_EQ(static_cast<int32_t>(fw::bytes::loadLe32(m.charge.raw)), -10000);
  EXPECT_EQ(fw::bytes::loadLe32(m.charge.raw + 4), 0xFFFFFFFFu) << "the high 16 bits, sign-extended";
  EXPECT_GE(fw::bytes::loadLe32(m.charge.raw + 8), 20u) << "time in 250 ms";
  // 2^47 - 1 wraps to -2^47.
  r.emu.presetChargeCount((int64_t{1} << 47) - 1);
  r.emu.setCurrentMa(1);
  r.harness.runFor(fw::s(2));
  r.emu.setCurrentMa(0);
  EXPECT_EQ(r.emu.chargeCount(), -(int64_t{1} << 47) + 1);
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(m7::sub::ResetPassq.address)), Status::Ok);
  EXPECT_EQ(r.emu.chargeCount(), 0);
}

}  // namespace
