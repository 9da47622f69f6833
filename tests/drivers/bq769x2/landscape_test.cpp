// The recurring BQ769x2 user problems reported on TI's E2E forum and by LibreSolar's bms-firmware users, one
// test each, on the
// emulator that reproduces them.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;

// (1) 0x08 is the 7-bit address, 0x10/0x11 the 8-bit forms on the wire (SLUSE13B section 14).
TEST(Bq769x2Landscape, SevenBitAddress0x08Is0x10OnTheWire) {
  EXPECT_EQ(drv::kDefaultAddress, 0x08);
  Rig good;
  ASSERT_EQ(good.runLink(good.driver.link().startRead(0x14, 2)), Status::Ok);
  EXPECT_EQ(good.wire().front(), "S 10 14 Sr 11 [74 0E] P");

  drv::MonitorConfig wrong;
  wrong.link.address = 0x10;  // the 8-bit write address used as a 7-bit one
  Rig bad(wrong);
  EXPECT_EQ(bad.runLink(bad.driver.link().startRead(0x14, 2)), Status::Nack);
  EXPECT_EQ(bad.wire().front(), "S 20 NACK P");  // nobody answers at 0x10 (0x20 on the wire)
}

// (1) CRC variant mismatch: a BQ7695202 ships with CRC on and NACKs frames without CRC.
TEST(Bq769x2Landscape, CrcVariantMismatchAndTheProbe) {
  Rig r;  // driver without CRC
  r.emu.setCrc(true);
  drv::Identity id;
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::DataNack);

  drv::MonitorConfig probe;
  probe.probeCrc = true;
  Rig p(probe);
  p.emu.setCrc(true);
  ASSERT_EQ(p.run(p.driver.startProbe(id)), Status::Ok);
  EXPECT_TRUE(id.crc);
  EXPECT_TRUE(p.driver.link().crc());
  EXPECT_EQ(p.wire().front(), "S 10 3E 01 00 NACK P") << "the first try is without CRC";
  EXPECT_TRUE(p.sawLine("S 10 3E 01 8A 00 00 P")) << "then with CRC: crc8(10 3E 01) = 0x8A";
  drv::Bq769x2Measurement m;
  ASSERT_EQ(p.scan(m), Status::Ok);  // and the link stays in CRC mode
  EXPECT_EQ(m.reg.cellMv[0], 3700);

  // The same probe against a device without CRC answers at once, and never sends a CRC-framed write.
  Rig q(probe);
  ASSERT_EQ(q.run(q.driver.startProbe(id)), Status::Ok);
  EXPECT_FALSE(id.crc);
  EXPECT_EQ(q.count("S 10 3E 01 8A"), 0u);
}

// (2) The first command after power-up is NACKed: one retry absorbs it.
TEST(Bq769x2Landscape, FirstCommandAfterPowerUpNacked) {
  Emu::Timing t;
  t.nackFirstAfterPowerUp = true;
  Rig r({}, t);
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 NACK P");
  EXPECT_EQ(r.driver.stats().errors[static_cast<int>(Status::Nack)], 1u);
}

// (4) Reading 0x40 too early returns the previous buffer. TI's example waits a fixed 2 ms and reads 32 bytes
// without checking anything; IROM_SIG takes ~8.5 ms, so it gets the previous command's data. The driver polls
// the echo and checks length and checksum.
TEST(Bq769x2Landscape, SubcommandReadTooEarlyGetsTheStaleBuffer) {
  Rig r;
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::sub::DeviceNumber.address, 2)), Status::Ok);
  // TI's pattern: write 0x3E, wait 2 ms, read 0x40.
  bool done = false;
  const uint8_t cmd[] = {0x3E, 0x04, 0x00};  // IROM_SIG
  uint8_t at = 0x40;
  uint8_t rx[32] = {};
  std::vector<fw::hal::I2cTransaction> write{{0x08, cmd, {}}};
  std::vector<fw::hal::I2cTransaction> read{{0x08, {&at, 1}, rx}};
  auto notify = fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done};
  ASSERT_EQ(r.bus.start(write, notify), Status::Ok);
  r.harness.runUntil([&] { return done; }, fw::ms(5));
  r.harness.runFor(fw::ms(2));
  done = false;
  ASSERT_EQ(r.bus.start(read, notify), Status::Ok);
  r.harness.runUntil([&] { return done; }, fw::ms(5));
  EXPECT_EQ(rx[0] | (rx[1] << 8), 0x7695) << "TI's blind read returns DEVICE_NUMBER's data for IROM_SIG";

  r.harness.runFor(fw::ms(20));
  const uint64_t t0 = r.harness.nowUs();
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::sub::IromSig.address, 2)), Status::Ok);
  EXPECT_GE(r.harness.nowUs() - t0, 8500u);
  const uint8_t* d = r.driver.link().data();
  EXPECT_EQ(d[0] | (d[1] << 8), 0xA53C) << "the driver waited for the echo";
}

// (4) Actual lengths differ from the TRM: FW_VERSION reports 11 bytes, 6 of them data. The 0x61 length is
// used for the checksum, the data are the first 6 bytes.
TEST(Bq769x2Landscape, FwVersionLengthDiffersFromTheTrm) {
  Rig r;
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(r.driver.link().reported(), 7);  // 0x61 = 11
  EXPECT_EQ(id.fwDevice(), 0x7695);          // big-endian device number inside FW_VERSION
  EXPECT_EQ(id.fwVersion(), 0x0100);
  EXPECT_EQ(id.fwBuild(), 0x0035);
}

// (5) Data-memory writes outside CONFIG_UPDATE, or with a wrong checksum or length, have no effect.
TEST(Bq769x2Landscape, DataMemoryWriteOutsideConfigUpdateHasNoEffect) {
  Rig r;
  const uint8_t value[] = {0x8C};
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandWrite(map::dm::EnabledProtectionsA.address, value)),
            Status::Ok);
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x88u);
  EXPECT_EQ(r.emu.rejectedWrites(), 1u);
  // A raw write with TI's length mistake (data + 2) inside CONFIG_UPDATE is refused too.
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::SetCfgupdate.address)), Status::Ok);
  r.harness.runFor(fw::ms(3));
  ASSERT_TRUE(r.emu.inConfigUpdate());
  const uint8_t data[] = {0x3E, 0x61, 0x92, 0x8C};
  const uint8_t tail[] = {0x60, 0x80, 0x03};
  bool done = false;
  auto notify = fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done};
  std::vector<fw::hal::I2cTransaction> list{{0x08, data, {}}, {0x08, tail, {}}};
  ASSERT_EQ(r.bus.start(list, notify), Status::Ok);
  r.harness.runUntil([&] { return done; }, fw::ms(5));
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x88u);
  EXPECT_EQ(r.emu.rejectedWrites(), 2u);
  // The driver's configure transaction does it right.
  const drv::Setting s[] = {drv::setting(map::dm::EnabledProtectionsA, map::bits::SafetyA::fromRaw(0x8C))};
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(s))), Status::Ok);
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x8Cu);
}

// (6) FETs stay off: the default Mfg Status Init leaves FET test mode on (FET_EN = 0), so ALL_FETS_ON alone
// does nothing. startFetEnable() sends FET_ENABLE only when FET_EN is 0 (it toggles), and never twice.
TEST(Bq769x2Landscape, FetsStayOffUntilFetEnable) {
  Rig r;
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOn)), Status::Ok);
  r.harness.runFor(fw::ms(1));
  EXPECT_FALSE(r.emu.chgFet());
  EXPECT_FALSE(r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  EXPECT_TRUE(r.emu.fetEnabled());
  r.harness.runFor(fw::ms(1));
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_TRUE(r.emu.dsgFet());
  EXPECT_EQ(r.count("S 10 3E 22 00 P"), 1u);
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);  // already enabled: no toggle
  EXPECT_EQ(r.count("S 10 3E 22 00 P"), 1u);
  EXPECT_TRUE(r.emu.fetEnabled());
}

// (6) Host intent apart from FET status; FET_STATUS is never written back (FET_CONTROL errata, E2E 1453973):
// "discharge off" is FET_CONTROL with the intent's OFF bits (DSG_OFF | PDSG_OFF = 0x03, SLUUCW9), whatever
// the FETs report.
TEST(Bq769x2Landscape, FetIntentIsKeptApartFromFetStatus) {
  Rig r;
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::DischargeOff)), Status::Ok);
  EXPECT_TRUE(r.sawLine("S 10 3E 97 00 03 P"));  // FET_CONTROL: PDSG_OFF | DSG_OFF
  EXPECT_TRUE(r.sawLine("S 10 60 65 05 P"));     // checksum ~(0x97 + 0x00 + 0x03), length 1 + 4
  r.harness.runFor(fw::ms(1));
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(r.driver.fetIntent().dischargeOff);
  EXPECT_FALSE(r.driver.fetIntent().chargeOff);
  EXPECT_FALSE(m.reg.fetStatus.dsg_fet());
  EXPECT_TRUE(m.reg.fetStatus.chg_fet());
  // The device opens CHG by itself (COV): the status changes, the host's intent does not.
  r.emu.setCellMv(3, 4500);
  r.harness.runFor(fw::ms(300));
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_FALSE(m.reg.fetStatus.chg_fet());
  EXPECT_TRUE(m.reg.safetyStatusA.cov());
  EXPECT_FALSE(r.driver.fetIntent().chargeOff);
  // ALL_FETS_ON clears the host's intent; COV still holds CHG off.
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOn)), Status::Ok);
  r.harness.runFor(fw::ms(1));
  EXPECT_FALSE(r.driver.fetIntent().dischargeOff);
  EXPECT_TRUE(r.emu.dsgFet());
  EXPECT_FALSE(r.emu.chgFet());
  EXPECT_EQ(r.count("S 10 3E 97 00 "), 1u) << "no FET_CONTROL write built from a status";
}

// (7) Current and cell voltages are signed; 1 mA userA saturates at +-32.767 A.
TEST(Bq769x2Landscape, SignedCurrentAndCellVoltages) {
  Rig r;
  r.emu.setCurrentMa(-20000);
  r.emu.setCellMv(16, -12);  // an unused input reads slightly negative
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.current, -20000);
  EXPECT_EQ(m.reg.cellMv[15], -12);
  r.emu.setCurrentMa(50000);
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.current, INT16_MAX) << "saturated at 32.767 A";
  // With USER_AMPS = 10 mA the same 50 A reads 5000.
  const drv::Setting tenMilliamps[] = {drv::setting(
      map::dm::DaConfiguration,
      map::bits::DaConfiguration::fromRaw(0x05).with_user_amps(map::enums::UserAmps::TenMilliAmp))};
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(tenMilliamps))), Status::Ok);
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.current, 5000);
  EXPECT_EQ(drv::currentMa(m.reg.current, 100), 50000);
}

// (8) Clock stretching beyond the bus timeout and a bus held low: bounded, recovered by the bus (9 clocks +
// STOP), and the operation retries from its first byte.
TEST(Bq769x2Landscape, StretchAndStuckBusAreBoundedAndRecovered) {
  Rig r;
  r.emu.stretchNext(fw::ms(40));
  r.bus.holdSdaLow(2);
  drv::Bq769x2Measurement m;
  const uint64_t t0 = r.harness.nowUs();
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_LT(r.harness.nowUs() - t0, 50000u);  // two bus timeouts (20 ms each), two short retry delays
  EXPECT_EQ(r.bus.recoveries(), 2u);
}

// (9) A retry restarts the whole transaction: the register address is sent again.
TEST(Bq769x2Landscape, RetryResendsTheRegisterAddress) {
  Rig r(crcConfig(true));
  r.emu.setCrc(true);
  r.emu.corruptNextRead(9);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x14, 8)), Status::Ok);
  const auto w = r.wire();
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].substr(0, 14), "S 10 14 Sr 11 ");
  EXPECT_EQ(w[1].substr(0, 14), "S 10 14 Sr 11 ");
}

// Balancing: cells beyond the device, and neighbours unless allowed (E2E 1505209). Three cells at once need
// Cell Balance Max Cells of 3 or more (the emulator refuses more, E2E 969824; the default is 1).
TEST(Bq769x2Landscape, BalancingMaskRules) {
  Rig r;
  r.emu.setDataMemory(map::dm::CellBalanceMaxCells.address, 4, 1);
  EXPECT_EQ(r.driver.startBalance(0x0003), Status::InvalidArgument);  // cells 1 and 2 are neighbours
  ASSERT_EQ(r.run(r.driver.startBalance(0x8005)), Status::Ok);        // cells 1, 3 and 16
  EXPECT_TRUE(r.sawLine("S 10 3E 83 00 05 80 P"));
  EXPECT_EQ(r.emu.balancing(), 0x8005);
  drv::MonitorConfig adjacent;
  adjacent.allowAdjacentBalancing = true;
  Rig a(adjacent);
  a.emu.setDataMemory(map::dm::CellBalanceMaxCells.address, 4, 1);
  ASSERT_EQ(a.run(a.driver.startBalance(0x0003)), Status::Ok);
  EXPECT_EQ(a.emu.balancing(), 0x0003);
  EXPECT_EQ(a.emu.balanceCounters().adjacent, 1u);  // taken, and the shared input resistor overheats
  Rig7690x s(Emu::Model::Bq76905);
  EXPECT_EQ(s.driver.startBalance(0x0020), Status::InvalidArgument);  // the BQ76905 has 5 cells
  ASSERT_EQ(s.run(s.driver.startBalance(0x0011)), Status::Ok);        // cells 1 and 5
  EXPECT_EQ(s.emu.balancing(), 0x0011);
}

}  // namespace
