// The gauge emulator on its own, driven by raw SMBus transactions (no driver): it must answer as the TRM and
// the SMBus specification say, so that the driver tests check the driver against the gauge, not against
// the driver's own assumptions.
#include <gtest/gtest.h>

#include <vector>

#include "rig.hpp"

namespace bq4050_test {
namespace {

struct Raw {
  Rig rig;
  // Runs one transaction; returns its status.
  Status run(std::vector<uint8_t> write, size_t readLen = 0, bool pec = false, bool block = false) {
    writeBuf = std::move(write);
    readBuf.assign(readLen, 0);
    std::vector<fw::hal::I2cTransaction> list{{Emu::kAddress, writeBuf, readBuf, pec, block}};
    bool done = false;
    const Status s =
        rig.bus.start(list, fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done});
    if (s != Status::Ok) return s;
    rig.harness.runUntil([&] { return done; }, fw::s(1));
    readCount = list[0].readCount;
    return list[0].status;
  }
  std::string last() const { return rig.bus.wireLog().back().text; }
  std::vector<uint8_t> writeBuf, readBuf;
  uint8_t readCount = 0;
};

TEST(Bq4050Emulator, ReadWordAppendsThePecOverAddressesCommandAndData) {
  Raw r;
  r.rig.emu.setTemperature(2982);  // 0x0BA6
  ASSERT_EQ(r.run({0x08}, 2, true), Status::Ok);
  EXPECT_EQ(r.last(), "S 16 08 Sr 17 [A6 0B " + hex({referenceCrc8({0x16, 0x08, 0x17, 0xA6, 0x0B})}) + "] P");
}

TEST(Bq4050Emulator, BlockReadStartsWithTheCount) {
  Raw r;
  ASSERT_EQ(r.run({0x22}, 33, true, true), Status::Ok);  // DeviceChemistry
  EXPECT_EQ(r.readCount, 5);
  EXPECT_EQ(std::string(r.readBuf.begin() + 1, r.readBuf.begin() + 5), "LION");
}

TEST(Bq4050Emulator, ManufacturerBlockAccessEchoesTheSubcommand) {
  // SLUUAQ3A ManufacturerBlockAccess(): write 44 [02 lo hi], read 44 -> [count lo hi data]; count counts the
  // echo.
  Raw r;
  ASSERT_EQ(r.run({0x44, 0x02, 0x57, 0x00}, 0, true), Status::Ok);  // ManufacturingStatus
  ASSERT_EQ(r.run({0x44}, 35, true, true), Status::Ok);
  EXPECT_EQ(r.readCount, 5);
  EXPECT_EQ(r.readBuf[0], 4);
  EXPECT_EQ(r.readBuf[1], 0x57);
  EXPECT_EQ(r.readBuf[2], 0x00);
  EXPECT_EQ(r.readBuf[3] | (r.readBuf[4] << 8), 0x0018) << "GAUGE_EN | FET_EN";
}

TEST(Bq4050Emulator, ManufacturerDataCarriesNoEcho) {
  // SLUUAQ3A: "The result reading from ManufacturerData() does not include the MAC command."
  Raw r;
  ASSERT_EQ(r.run({0x00, 0x01, 0x00}), Status::Ok);  // word write DeviceType to ManufacturerAccess
  ASSERT_EQ(r.run({0x23}, 33, false, true), Status::Ok);
  EXPECT_EQ(r.readCount, 3);
  EXPECT_EQ(r.readBuf[0], 2);
  EXPECT_EQ(r.readBuf[1] | (r.readBuf[2] << 8), 0x4050);
}

TEST(Bq4050Emulator, UnknownCommandIsRefusedAndUnknownSubcommandSetsTheErrorCode) {
  Raw r;
  EXPECT_EQ(r.run({0x45}, 2), Status::DataNack);
  EXPECT_EQ(r.last(), "S 16 45 NACK P");
  ASSERT_EQ(r.run({0x00, 0x34, 0x12}), Status::Ok);  // subcommand 0x1234 does not exist
  EXPECT_EQ(r.rig.emu.word(0x16) & 0x000F, 3) << "BatteryStatus[EC] = UnsupportedCommand";
}

TEST(Bq4050Emulator, FetTogglesFollowTheTrm) {
  Raw r;
  auto& emu = r.rig.emu;
  EXPECT_TRUE(emu.chgFet());
  EXPECT_TRUE(emu.dsgFet());
  ASSERT_EQ(r.run({0x00, 0x1F, 0x00}), Status::Ok);  // CHGFET toggle: ignored while FET_EN = 1
  EXPECT_EQ(emu.manufacturingStatus(), 0x0018);
  ASSERT_EQ(r.run({0x00, 0x22, 0x00}), Status::Ok);  // FETControl: FET_EN -> 0, FETs off
  EXPECT_EQ(emu.manufacturingStatus(), 0x0008);
  EXPECT_FALSE(emu.chgFet());
  EXPECT_FALSE(emu.dsgFet());
  ASSERT_EQ(r.run({0x00, 0x20, 0x00}), Status::Ok);  // DSGFET on
  ASSERT_EQ(r.run({0x00, 0x1F, 0x00}), Status::Ok);  // CHGFET on
  EXPECT_TRUE(emu.chgFet());
  EXPECT_TRUE(emu.dsgFet());
  EXPECT_EQ(emu.operationStatus() & 0x6, 0x6u);
  ASSERT_EQ(r.run({0x00, 0x22, 0x00}), Status::Ok);  // back to firmware control
  EXPECT_EQ(emu.manufacturingStatus() & 0x0010, 0x0010);
  EXPECT_EQ(emu.operationStatus() & 0x6, 0x6u) << "the gauge's firmware drives both FETs";
}

TEST(Bq4050Emulator, ChgFetStaysOffWithDsgOffAbove16V) {
  Raw r;
  auto& emu = r.rig.emu;
  emu.setVoltage(16800);
  emu.setManufacturingStatus(0x0008);
  ASSERT_EQ(r.run({0x00, 0x1F, 0x00}), Status::Ok);
  EXPECT_EQ(emu.manufacturingStatus() & 0x2, 0x2) << "flag set";
  EXPECT_FALSE(emu.chgFet()) << "FET off (TI E2E 1445117)";
  ASSERT_EQ(r.run({0x00, 0x20, 0x00}), Status::Ok);
  EXPECT_TRUE(emu.chgFet()) << "on once DSG is on";
}

TEST(Bq4050Emulator, SealedGaugeIgnoresFetControl) {
  Raw r;
  r.rig.emu.setSealed(true);
  ASSERT_EQ(r.run({0x00, 0x22, 0x00}), Status::Ok);
  EXPECT_EQ(r.rig.emu.manufacturingStatus(), 0x0018);
  EXPECT_EQ(r.rig.emu.word(0x16) & 0x000F, 4) << "AccessDenied";
  EXPECT_EQ(r.rig.emu.operationStatus() & 0x300, 0x300u) << "SEC = SEALED";
}

TEST(Bq4050Emulator, FaultsActOnlyOnTheTransactionsTheyName) {
  Raw r;
  r.rig.emu.inject({.kind = Emu::FaultKind::TopBitStuck, .command = 0x09});
  ASSERT_EQ(r.run({0x08}, 2, true), Status::Ok) << "another command is untouched";
  EXPECT_EQ(r.run({0x09}, 2, true), Status::Pec);
  EXPECT_EQ(r.last(), "S 16 09 Sr 17 [98 BA 84] P");
  EXPECT_EQ(r.run({0x09}, 2, true), Status::Ok) << "once";
  EXPECT_EQ(r.rig.emu.pendingFaults(), 0u);
}

// The charge state followed no current: RelativeStateOfCharge stayed at 80 % whatever flowed. With a clock
// the gauge counts charge (SLUUAQ3A: Current() mA, RemainingCapacity() mAh with BatteryMode()[CAPM] = 0,
// RelativeStateOfCharge() % of FullChargeCapacity()), read back over SMBus as the driver reads it.
TEST(Bq4050Emulator, ChargeStateFollowsTheCurrentOnceAClockIsAttached) {
  Raw r;
  auto word = [&](uint8_t command) {
    EXPECT_EQ(r.run({command}, 2), Status::Ok);
    return static_cast<uint16_t>(r.readBuf[0] | r.readBuf[1] << 8);
  };
  // `ma` flows for `seconds`, then stops (the reads in between take bus time, and move no charge).
  auto flow = [&](int16_t ma, uint32_t seconds) {
    r.rig.emu.setCurrent(ma);
    r.rig.harness.runFor(fw::s(seconds));
    r.rig.emu.setCurrent(0);
  };
  flow(-4000, 1);
  EXPECT_EQ(word(0x0F), 3200) << "no clock: nothing is counted";
  r.rig.emu.attachClock(r.rig.harness.clock);
  flow(-4000, 360);  // 4 A for a tenth of an hour: 400 mAh out
  EXPECT_EQ(word(0x0F), 2800);
  EXPECT_EQ(word(0x0D), 70) << "2800 of 4000 mAh";
  EXPECT_EQ(word(0x10), 4000) << "FullChargeCapacity is not learned";
  flow(2000, 1800);  // charging: 2 A for half an hour, 1000 mAh in
  EXPECT_EQ(word(0x0F), 3800);
  EXPECT_EQ(word(0x0D), 95);
  flow(2000, 3600);
  EXPECT_EQ(word(0x0F), 4000) << "never above FullChargeCapacity";
  EXPECT_EQ(word(0x0D), 100);
  flow(-1, 3599);  // 1 mA for 3599 s: not yet a whole mAh
  EXPECT_EQ(word(0x0F), 4000);
  flow(-1, 1);
  EXPECT_EQ(word(0x0F), 3999);
  EXPECT_EQ(word(0x0D), 100) << "99.975 % rounds up";
}

TEST(Bq4050Emulator, WithCapmTheChargeStateCountsEnergyIn10mWh) {
  Raw r;
  r.rig.emu.setWord(0x03, 0x8000);  // BatteryMode()[CAPM]: capacities in 10 mWh
  r.rig.emu.setFullChargeCapacity(6000);
  r.rig.emu.setRemainingCapacity(3000);
  r.rig.emu.setVoltage(15000);
  r.rig.emu.attachClock(r.rig.harness.clock);
  r.rig.emu.setCurrent(-2000);  // 30 W for an hour: 30 Wh = 3000 x 10 mWh
  r.rig.harness.runFor(fw::s(3600));
  ASSERT_EQ(r.run({0x0F}, 2), Status::Ok);
  EXPECT_EQ(r.readBuf[0] | r.readBuf[1] << 8, 0);
  ASSERT_EQ(r.run({0x0D}, 2), Status::Ok);
  EXPECT_EQ(r.readBuf[0] | r.readBuf[1] << 8, 0);
}

}  // namespace
}  // namespace bq4050_test
