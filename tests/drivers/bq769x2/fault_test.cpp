// Acceptance 2: every fault the emulator can inject. For each: the driver ends with the right status, never
// hands out a value from a transaction that did not validate (the output record keeps its sentinel), every
// wait is bounded (virtual-time limits below), and the next operation after the fault clears succeeds.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;

drv::Bq769x2Measurement sentinel() {
  drv::Bq769x2Measurement m;
  m.takenAt = fw::Instant{0xDEADBEEF};
  m.reg.cellMv[0] = -999;
  return m;
}
bool untouched(const drv::Bq769x2Measurement& m) {
  return m.takenAt.us == 0xDEADBEEF && m.reg.cellMv[0] == -999;
}
drv::MonitorConfig noRetries(bool crc = false) {
  drv::MonitorConfig c;
  c.link.retries = 0;
  c.link.crc = crc;
  return c;
}

TEST(Bq769x2Faults, AddressNackIsNackAndRecovers) {
  Rig r;
  r.emu.nackNext(3);  // the first attempt and both retries
  auto m = sentinel();
  const uint64_t t0 = r.harness.nowUs();
  EXPECT_EQ(r.scan(m), Status::Nack);
  EXPECT_TRUE(untouched(m));
  EXPECT_LT(r.harness.nowUs() - t0, 5000u);  // 3 attempts, 2 retry delays
  EXPECT_EQ(r.driver.stats().errors[static_cast<int>(Status::Nack)], 3u);
  EXPECT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.cellMv[0], 3700);
}

TEST(Bq769x2Faults, NackOfTheFirstTransactionAfterPowerUpIsRetried) {
  Emu::Timing t;
  t.nackFirstAfterPowerUp = true;
  Rig r({}, t);
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 NACK P");
  EXPECT_EQ(r.wire()[1], "S 10 3E 01 00 P") << "the retry resends the whole transaction";
  EXPECT_EQ(r.driver.stats().retries, 1u);
  EXPECT_EQ(id.deviceNumber, 0x7695);
}

TEST(Bq769x2Faults, DataNackOfAWrite) {
  Rig plain(noRetries(false));  // the driver sends no CRC to a device in CRC mode: refused at the CRC byte
  plain.emu.setCrc(true);
  EXPECT_EQ(plain.runLink(plain.driver.link().startSubcommand(map::sub::FetEnable.address)),
            Status::DataNack);
  EXPECT_EQ(plain.wire().front(), "S 10 3E 22 00 NACK P");
  plain.harness.runFor(fw::ms(1));
  EXPECT_FALSE(plain.emu.fetEnabled()) << "a refused write has no effect";
}

TEST(Bq769x2Faults, ClockStretchPastTheBusLimitTimesOutAndRecovers) {
  Rig r;
  r.emu.stretchNext(fw::ms(30));  // the bus gives up after 20 ms
  auto m = sentinel();
  const uint64_t t0 = r.harness.nowUs();
  ASSERT_EQ(r.scan(m), Status::Ok);           // the retry goes through
  EXPECT_LT(r.harness.nowUs() - t0, 26000u);  // the 20 ms bus limit, the retry delay and one scan
  EXPECT_EQ(r.driver.stats().errors[static_cast<int>(Status::Timeout)], 1u);
  EXPECT_NE(r.wireText().find("TIMEOUT RECOVERY"), std::string::npos);

  // A device that stretches every transaction: Timeout after every attempt, bounded by 3 x the bus limit.
  Emu::Timing stuck;
  stuck.ackStretch = fw::ms(25);
  Rig s({}, stuck);
  auto n = sentinel();
  const uint64_t t1 = s.harness.nowUs();
  EXPECT_EQ(s.scan(n, fw::ms(500)), Status::Timeout);
  EXPECT_TRUE(untouched(n));
  EXPECT_LT(s.harness.nowUs() - t1, 3 * 21000u + 2000u);
}

TEST(Bq769x2Faults, CorruptedDataByteInCrcModeIsCrc) {
  Rig r(noRetries(true));
  r.emu.setCrc(true);
  r.emu.corruptNextRead(6);  // a data byte (even wire index) of the first scan read
  auto m = sentinel();
  EXPECT_EQ(r.scan(m), Status::Crc);
  EXPECT_TRUE(untouched(m));
  EXPECT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.cellMv[0], 3700);
}

TEST(Bq769x2Faults, CorruptedCrcByteIsCrcAndTheRetryRestartsTheRead) {
  Rig r(crcConfig(true));
  r.emu.setCrc(true);
  r.emu.corruptNextRead(1);  // the first CRC byte
  auto m = sentinel();
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(r.driver.stats().errors[static_cast<int>(Status::Crc)], 1u);
  // The failed read and its retry both start with the register address (LibreSolar #53); the charge
  // request (a write) comes first.
  const auto w = r.wire();
  ASSERT_GE(w.size(), 3u);
  EXPECT_EQ(w[0].substr(0, 10), "S 10 3E 76");
  EXPECT_EQ(w[1].substr(0, 13), "S 10 0A Sr 11");
  EXPECT_EQ(w[2].substr(0, 13), "S 10 0A Sr 11");
}

TEST(Bq769x2Faults, CorruptedBufferByteWithoutCrcIsCaughtByTheChecksum) {
  Rig r(noRetries());
  // Without CRC a flipped bit in the buffer (its first data byte; the echo polls are the two reads before
  // it) is caught by the 0x60 checksum.
  r.emu.corruptNextRead(0, 2);
  EXPECT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::sub::DeviceNumber.address, 2)),
            Status::Checksum);
}

TEST(Bq769x2Faults, WrongLengthIsLength) {
  Rig r(noRetries());
  drv::Identity id;
  r.emu.wrongLengthNext(40);  // more than the 32-byte buffer + 4
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Length);
  r.emu.wrongLengthNext(5);  // DEVICE_NUMBER needs 2 data bytes, 5 announces 1
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Length);
  EXPECT_EQ(id.deviceNumber, 0);  // nothing reported
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(id.deviceNumber, 0x7695);
}

TEST(Bq769x2Faults, WrongChecksumIsChecksum) {
  Rig r(noRetries());
  drv::Identity id;
  r.emu.wrongChecksumNext();
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Checksum);
  EXPECT_EQ(id.deviceNumber, 0);
  Rig retrying;
  retrying.emu.wrongChecksumNext();
  EXPECT_EQ(retrying.run(retrying.driver.startProbe(id)), Status::Ok);
}

TEST(Bq769x2Faults, StaleBufferIsDetectedAndNeverReported) {
  Rig r(noRetries());
  // The previous subcommand's result is still in the buffer when the echo appears.
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::sub::ManufacturingStatus.address, 2)),
            Status::Ok);
  r.emu.staleBufferNext(fw::ms(2));
  drv::Identity id;
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Checksum);  // MANUFACTURINGSTATUS data under code 0x0001
  EXPECT_EQ(id.deviceNumber, 0);
  r.emu.staleBufferNext(fw::ms(2));
  Rig retrying;
  retrying.emu.staleBufferNext(fw::ms(2));
  EXPECT_EQ(retrying.run(retrying.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(id.deviceNumber, 0x7695);
}

TEST(Bq769x2Faults, EchoThatNeverComesIsTimeoutWithinTheBudget) {
  Rig r(noRetries());
  r.emu.setLatency(map::sub::DeviceNumber.address, fw::ms(50));
  drv::Identity id;
  const uint64_t t0 = r.harness.nowUs();
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Timeout);
  const uint64_t took = r.harness.nowUs() - t0;
  EXPECT_GE(took, 10000u);  // the budget covers IROM_SIG's ~8.5 ms
  EXPECT_LT(took, 20000u);
}

// A poll whose two bytes straddle the end of the command reads 0x3E busy (FF) and 0x3F already echoed: the
// command ran, so the link polls once more instead of restarting the operation (which would send the command
// again: ALL_FETS_OFF twice, 2.5 ms instead of 1.6 ms on the L1306 twin's fast path).
TEST(Bq769x2Faults, APollThatStraddlesTheEndOfTheCommandPollsAgain) {
  Rig r(noRetries());
  r.emu.straddleNextEcho();
  EXPECT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::AllFetsOff.address)), Status::Ok);
  EXPECT_EQ(r.wire(), (std::vector<std::string>{"S 10 3E 95 00 P", "S 10 3E Sr 11 [FF 00] P",
                                                "S 10 3E Sr 11 [95 00] P"}));
}

TEST(Bq769x2Faults, EchoOfAnotherCommandIsEchoMismatch) {
  Emu::Timing t;
  t.boot = {};
  Rig r(noRetries(), t);
  drv::Identity id;
  ASSERT_EQ(r.driver.startProbe(id), Status::Ok);
  r.harness.runFor(fw::us(150));  // after the 0x3E write, before the first poll
  r.emu.reset();                  // the device forgets the command: 0x3E/0x3F read 00 00
  EXPECT_EQ(r.finish(Status::Ok), Status::EchoMismatch);
  EXPECT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
}

TEST(Bq769x2Faults, DeviceResetMidReadRestartsTheSnapshot) {
  Emu::Timing t;
  t.boot = fw::ms(1);  // within the link's two retries, 500 us apart, after the rest of the read
  Rig r({}, t);
  auto m = sentinel();
  // Inside the first read (26 bytes of the cell block): the rest of it reads 0xFF, the next read is NACKed
  // while the device boots and succeeds on a retry; the retry makes the scan start over, so the record is
  // one consistent snapshot taken after the reset.
  r.emu.resetAfterBytes(12);
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(r.count("S 10 0A Sr 11 ["), 2u) << r.wireText();
  for (int c = 0; c < 16; ++c)
    EXPECT_EQ(m.reg.cellMv[c], 3700);
  EXPECT_TRUE(m.reg.batteryStatus.por()) << "the reset shows in Battery Status[POR]";
  EXPECT_EQ(r.emu.resets(), 1u);
}

TEST(Bq769x2Faults, DeviceResetWithALongBootNeverYieldsARecord) {
  Emu::Timing slowBoot;
  slowBoot.boot = fw::ms(10);
  Rig r({}, slowBoot);
  auto m = sentinel();
  r.emu.resetAfterBytes(12);
  EXPECT_EQ(r.scan(m), Status::Nack);
  EXPECT_TRUE(untouched(m));
  r.harness.runFor(fw::ms(10));
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.cellMv[0], 3700);
}

TEST(Bq769x2Faults, DeviceResetInTheLastReadOfAScanIsImplausible) {
  Emu::Timing t;
  t.boot = {};  // no NACK window: only the data tell
  Rig r(drv::MonitorConfig{}, t);
  auto m = sentinel();
  // Bytes: the DASTATUS6 request 4, 0x0A read = 3 + 26, 0x24 read = 3 + 24, 0x62 read = 3 + 20, 0x02 read =
  // 3 + 6, then the 0x7F read's 3 address and command bytes and its data byte, which the device no longer
  // drives.
  r.emu.resetAfterBytes(4 + 29 + 27 + 23 + 9 + 4);
  EXPECT_EQ(r.scan(m), Status::Implausible);  // FET Status read as 0xFF: reserved bit 7 set
  EXPECT_TRUE(untouched(m));
  EXPECT_EQ(r.scan(m), Status::Ok);
}

TEST(Bq769x2Faults, ReadThatNeededARetryRestartsTheWholeScan) {
  Rig r;
  auto m = sentinel();
  r.harness.runFor(fw::us(10));
  // Fail the second read once: the scan starts over from its charge request (the request, the five reads with
  // one retried, then the request and the five reads: 13 transactions; the next scan reads the charge).
  ASSERT_EQ(r.driver.startScan(m), Status::Ok);
  ASSERT_TRUE(r.harness.runUntil([&] { return r.bus.transactions() == 2; }, fw::ms(10)));
  r.emu.nackNext(1);
  ASSERT_EQ(r.finish(Status::Ok), Status::Ok);
  EXPECT_EQ(r.count("S 10 0A Sr 11 ["), 2u) << r.wireText();
  EXPECT_EQ(r.count("S 10 3E 76 00 P"), 2u) << r.wireText();
  EXPECT_EQ(r.bus.transactions(), 13u);
}

TEST(Bq769x2Faults, BusStuckLowIsBusStuckThenRecovers) {
  Rig r;
  r.bus.holdSdaLow(-1);
  auto m = sentinel();
  const uint64_t t0 = r.harness.nowUs();
  EXPECT_EQ(r.scan(m, fw::ms(500)), Status::BusStuck);
  EXPECT_TRUE(untouched(m));
  EXPECT_LT(r.harness.nowUs() - t0, 3 * 21000u + 2000u);
  r.bus.holdSdaLow(3);  // released after three recovery clocks
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_NE(r.wireText().find("BUS LOW TIMEOUT RECOVERY"), std::string::npos);
}

TEST(Bq769x2Faults, BusyWhileAnOperationRuns) {
  Rig r;
  drv::Bq769x2Measurement m;
  drv::Identity id;
  ASSERT_EQ(r.driver.startScan(m), Status::Ok);
  EXPECT_EQ(r.driver.startProbe(id), Status::Busy);
  EXPECT_EQ(r.driver.link().startRead(0x14, 2), Status::Busy);
  EXPECT_EQ(r.finish(Status::Ok), Status::Ok);
  EXPECT_EQ(r.driver.link().startRead(0x14, 0), Status::InvalidArgument);
  EXPECT_EQ(r.driver.link().startRead(0x14, drv::kMaxReadBytes + 1), Status::InvalidArgument);
  const uint8_t five[5] = {};
  EXPECT_EQ(r.driver.link().startWrite(0x66, five), Status::InvalidArgument);
  EXPECT_EQ(r.driver.startConfigure({}), Status::InvalidArgument);
}

}  // namespace
