// The scan: one typed measurement record from one validated pass over the gauge, and its cost on the wire.
#include <gtest/gtest.h>

#include <cstdio>

#include "rig.hpp"

namespace bq4050_test {
namespace {

TEST(Bq4050Scan, PublishesTheTypedRecord) {
  Rig rig;
  rig.emu.setVoltage(14820);
  rig.emu.setCurrent(-2345);
  rig.emu.setTemperature(3032);  // 30.0 degC
  rig.emu.setRsoc(57);
  rig.emu.setRemainingCapacity(2280);
  rig.emu.setFullChargeCapacity(4000);
  rig.emu.setTimeToEmpty(58);
  rig.emu.setTimeToFull(0xFFFF);
  rig.emu.setBatteryStatus(0x02C0);  // RCA | INIT | DSG
  rig.emu.setCells({3701, 3702, 3703, 3714});
  rig.emu.setSafetyStatus(0x00000010);  // OCD1
  rig.emu.setPfStatus(0);
  rig.harness.runFor(fw::ms(7));
  const uint64_t start = rig.harness.nowUs();
  bq::Measurement m;
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_EQ(m.takenAt.us, static_cast<uint32_t>(start));
  EXPECT_EQ(m.voltageMv, 14820);
  EXPECT_EQ(m.currentMa, -2345);
  EXPECT_EQ(m.temperatureDeciK, 3032);
  EXPECT_EQ(m.rsocPercent, 57);
  EXPECT_EQ(m.remainingCapacity, 2280);
  EXPECT_EQ(m.fullChargeCapacity, 4000);
  EXPECT_EQ(m.timeToEmptyMin, 58);
  EXPECT_EQ(m.timeToFullMin, 0xFFFF);
  EXPECT_TRUE(m.batteryStatus.rca());
  EXPECT_TRUE(m.batteryStatus.init());
  EXPECT_TRUE(m.batteryStatus.dsg());
  EXPECT_FALSE(m.batteryStatus.fc());
  EXPECT_EQ(m.cellCount, 4);
  EXPECT_EQ(m.cells().size(), 4u);
  EXPECT_EQ(m.cellMv[0], 3701);
  EXPECT_EQ(m.cellMv[3], 3714);
  EXPECT_TRUE(m.safetyStatus.ocd1());
  EXPECT_FALSE(m.safetyStatus.cuv());
  EXPECT_TRUE(m.deviceFault());
  EXPECT_TRUE(m.operationStatus.chg());
  EXPECT_TRUE(m.operationStatus.dsg());
  EXPECT_EQ(m.operationStatus.raw() & 0x300u, 0x200u) << "SEC = UNSEALED";
  EXPECT_EQ(rig.gauge.stats().published, 1u);
}

TEST(Bq4050Scan, FollowsStatusChanges) {
  Rig rig;
  bq::Measurement m;
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_FALSE(m.deviceFault());
  EXPECT_FALSE(m.batteryStatus.ota());
  rig.emu.setBatteryStatus(0x10C0);      // OTA
  rig.emu.setSafetyStatus(0x00002000);   // OTD
  rig.emu.setFirmwareFets(true, false);  // the gauge opened DSG
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_TRUE(m.batteryStatus.ota());
  EXPECT_TRUE(m.safetyStatus.otd());
  EXPECT_TRUE(m.deviceFault());
  EXPECT_FALSE(m.operationStatus.dsg());
  EXPECT_TRUE(m.operationStatus.chg());
  rig.emu.setPfStatus(0x00000001);
  rig.emu.setSafetyStatus(0);
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_EQ(m.pfStatus, 1u);
  EXPECT_TRUE(m.deviceFault());
}

TEST(Bq4050Scan, ReadsOnlyTheConfiguredCells) {
  bq::GaugeConfig cfg = config(bq::PecMode::On);
  cfg.cells = 2;
  Rig rig(cfg);
  bq::Measurement m;
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_EQ(m.cellCount, 2);
  EXPECT_EQ(m.cells().size(), 2u);
  EXPECT_EQ(m.cellMv[2], 0);
  for (const auto& line : rig.wire()) {
    EXPECT_EQ(line.find("S 16 3D"), std::string::npos);
    EXPECT_EQ(line.find("S 16 3C"), std::string::npos);
  }
}

TEST(Bq4050Scan, ImplausibleValueThatPersistsFailsTheScanAndPublishesNothing) {
  Rig rig;
  rig.emu.setCell(2, 5100);  // above the 5000 mV cell input range
  bq::Measurement m;
  m.voltageMv = 7;
  EXPECT_EQ(rig.scan(m), Status::Implausible);
  EXPECT_EQ(m.voltageMv, 7);
  EXPECT_EQ(rig.gauge.stats().rejected(), 1u + rig.gauge.config().retries);
}

// Wire time of one transaction at 100 kHz: START, 9 bit times per byte, a repeated START if it reads, STOP.
uint64_t wireUs(int bytes, bool repeatedStart) {
  return (1 + 9 * bytes + (repeatedStart ? 1 : 0) + 1) * 10;
}

TEST(Bq4050Scan, FiguresAt100kHzWithAndWithoutPec) {
  for (bq::PecMode pec : {bq::PecMode::On, bq::PecMode::Off}) {
    const bool on = pec == bq::PecMode::On;
    Rig rig(config(pec));
    bq::Measurement m;
    const uint64_t t0 = rig.harness.nowUs();
    ASSERT_EQ(rig.scan(m), Status::Ok);
    const uint64_t wallUs = rig.harness.nowUs() - t0;
    // Expected from the protocol alone: 13 word reads (addr, cmd, addr, lo, hi [, PEC]) and 3 MAC reads of
    // 4 bytes: a block write (addr, 44, 02, lo, hi [, PEC]) and a block read (addr, 44, addr, count, echo x2,
    // 4 data [, PEC]). Without PEC every read is made twice.
    const int p = on ? 1 : 0;
    const int reads = on ? 1 : 2;
    const uint64_t words = 13 * reads * wireUs(5 + p, true);
    const uint64_t macs = 3 * (wireUs(5 + p, false) + reads * wireUs(10 + p, true));
    const uint64_t transactions = 13 * reads + 3 * (1 + reads);
    EXPECT_EQ(rig.bus.transactions(), transactions);
    EXPECT_EQ(rig.gauge.stats().transactions, transactions);
    EXPECT_EQ(rig.bus.busTimeUs(), words + macs);
    std::printf(
        "REPORT bq4050.scan.transactions=%llu bus_us=%llu wall_us=%llu pec=%s pace_us=%u bit_rate=100000\n",
        static_cast<unsigned long long>(rig.bus.transactions()),
        static_cast<unsigned long long>(rig.bus.busTimeUs()), static_cast<unsigned long long>(wallUs),
        on ? "on" : "off", rig.gauge.config().pace.us);
  }
}

TEST(Bq4050Scan, ScanEveryHalfSecondForAMinuteWithRareFaults) {
  // A minute of scans at 2 Hz with a fault every few scans: every published record is the pack's true
  // state, every fault is counted, and no scan is lost to a single fault.
  Rig rig;
  using K = Emu::FaultKind;
  const Emu::Fault faults[] = {{.kind = K::TopBitStuck, .command = 0x09},
                               {.kind = K::AllOnes, .command = 0x3E},
                               {.kind = K::Asleep},
                               {.kind = K::AddressNack},
                               {.kind = K::CorruptByte, .command = 0x44, .index = 4, .value = 0x20},
                               {.kind = K::Stretch, .command = 0x0A, .stretch = fw::ms(35)}};
  int published = 0;
  for (int i = 0; i < 120; ++i) {
    if (i % 5 == 0) rig.emu.inject(faults[(i / 5) % 6]);
    rig.emu.setVoltage(static_cast<uint16_t>(14000 + i));
    bq::Measurement m;
    ASSERT_EQ(rig.scan(m), Status::Ok) << "scan " << i;
    EXPECT_EQ(m.voltageMv, 14000 + i);
    EXPECT_EQ(m.cellMv[1], 3750);
    EXPECT_EQ(m.safetyStatus.raw(), 0u);
    ++published;
    rig.harness.runFor(fw::ms(500));
  }
  const auto& s = rig.gauge.stats();
  EXPECT_EQ(published, 120);
  EXPECT_EQ(s.published, 120u);
  EXPECT_EQ(s.pecErrors(), 16u) << "TopBitStuck, AllOnes, Asleep and CorruptByte, 4 times each";
  EXPECT_EQ(s.count(Status::Nack), 4u);
  EXPECT_EQ(s.count(Status::Timeout), 4u);
  std::printf("REPORT bq4050.soak scans=120 published=%u pec_errors=%u nacks=%u timeouts=%u retries=%u\n",
              s.published, s.pecErrors(), s.count(Status::Nack), s.count(Status::Timeout), s.retries);
}

}  // namespace
}  // namespace bq4050_test
