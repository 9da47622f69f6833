// Periodic scans: values as the emulated chips hold them, units, validity, timing against the wire minimum.
#include <gtest/gtest.h>

#include <cstdio>

#include "chain_rig.hpp"
#include "drivers/bq79616/registers.hpp"
#include "regmap/bq79616.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
namespace r = fw::regmap::bq79616::reg;
using fw::Status;
using test::ChainRig;

TEST(Bq79616Scan, RecordsHoldWhatTheChipsMeasure) {
  ChainRig rig(3);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.setCellMicrovolts(1, 16, 1110811);  // 0x16C0, the app note's first CAN bytes
  rig.emulator.setCellMicrovolts(2, 1, 4200000);
  rig.emulator.setCellRaw(0, 5, -12);       // a negative reading stays negative
  rig.emulator.setDieTempRaw(2, 1, -1000);  // -25 degC
  rig.emulator.setGpioRaw(1, 3, 9830);      // 1.5 V at 152.59 uV
  const uint64_t before = rig.harness.nowUs();
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.summary.devices, 3);
  EXPECT_EQ(rig.summary.validDevices, 3);
  EXPECT_EQ(rig.summary.faultedDevices, 0);
  EXPECT_EQ(rig.summary.firstError.device, bq::kNoDevice);
  for (uint8_t d = 0; d < 3; ++d) {
    const auto& rec = rig.records[d];
    EXPECT_EQ(rec.valid, bq::kValidCells | bq::kValidDieTemp | bq::kValidGpio | bq::kValidFaults);
    EXPECT_EQ(rec.status, Status::Ok);
    for (int c = 1; c <= 16; ++c)
      EXPECT_EQ(rec.cellRaw[c - 1], rig.emulator.cellRaw(d, c)) << "device " << int(d) << " cell " << c;
    EXPECT_GE(rec.takenAt.us, before);
    EXPECT_LE(rec.takenAt.us, rig.summary.finished.us);
  }
  EXPECT_EQ(rig.records[1].cellRaw[15], 0x16C0);
  EXPECT_EQ(bq::cellMicrovolts(rig.records[1].cellRaw[15]), 1110812);  // 5824 x 190.73 uV
  EXPECT_EQ(bq::cellMicrovolts(rig.records[2].cellRaw[0]), 4200065);   // nearest code to 4.2 V
  EXPECT_EQ(rig.records[0].cellRaw[4], -12);
  EXPECT_EQ(rig.records[2].dieTemp[0], 2482);  // -25 degC = 248.15 K
  EXPECT_EQ(rig.records[0].dieTemp[1], 2982);  // 25 degC
  EXPECT_EQ(rig.records[1].gpioRaw[2], 9830);
  EXPECT_EQ(rig.records[1].gpioRaw[0], bq::regs::kNotReady) << "GPIOs not set up as ADC inputs read 0x8000";
}

// One unconverted reading (0x8000) in either die temperature makes that part NotReady, the other parts of the
// device still validate. (The emulator clamps a cell code set directly to +-32767, so cells reach 0x8000 only
// before the ADC settled: ReadingsBeforeTheAdcSettledAreNotReadyNotValues.)
TEST(Bq79616Scan, EitherDieTemperatureNotConvertedMakesThatPartNotReady) {
  ChainRig rig(2);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  ASSERT_EQ(rig.scan(), Status::Ok);
  for (int t = 1; t <= 2; ++t) {
    rig.emulator.setDieTempRaw(1, t, bq::regs::kNotReady);
    EXPECT_EQ(rig.scan(), Status::NotReady) << "die temperature " << t;
    EXPECT_EQ(rig.records[1].valid & bq::kValidDieTemp, 0) << "die temperature " << t;
    EXPECT_NE(rig.records[1].valid & bq::kValidCells, 0) << "die temperature " << t;
    EXPECT_NE(rig.records[0].valid & bq::kValidDieTemp, 0) << "die temperature " << t;
    rig.emulator.setDieTempRaw(1, t, 1000);
  }
  EXPECT_EQ(rig.scan(), Status::Ok);
}

TEST(Bq79616Scan, UnitConversionsAreExactIntegers) {
  EXPECT_EQ(bq::cellMicrovolts(0), 0);
  EXPECT_EQ(bq::cellMicrovolts(1), 191);  // 190.73 rounds up
  EXPECT_EQ(bq::cellMicrovolts(-1), -191);
  EXPECT_EQ(bq::cellMicrovolts(32767), 6249650);  // 32767 x 190.73 = 6249649.91
  EXPECT_EQ(bq::cellMicrovolts(-32767), -6249650);
  EXPECT_EQ(bq::dieTempDeciKelvin(0), 2732);      // 273.15 K rounds half up
  EXPECT_EQ(bq::dieTempDeciKelvin(4000), 3732);   // 100 degC
  EXPECT_EQ(bq::dieTempDeciKelvin(-1600), 2332);  // -40 degC
  EXPECT_EQ(bq::dieTempDeciKelvin(-32768), -5460);
}

TEST(Bq79616Scan, ReadingsBeforeTheAdcSettledAreNotReadyNotValues) {
  auto config = test::configFor(2);
  config.adcSettle = fw::us(0);  // skip the LPF settling the emulator, like the chip, needs
  ChainRig rig(2, config);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  EXPECT_EQ(rig.scan(), Status::NotReady);
  EXPECT_EQ(rig.records[0].status, Status::NotReady);
  EXPECT_EQ(rig.records[0].valid & bq::kValidCells, 0);
  EXPECT_EQ(rig.records[0].cellRaw[0], 0);
  EXPECT_NE(rig.records[0].valid & bq::kValidDieTemp, 0) << "the other parts are still good";
  rig.harness.runFor(fw::ms(40));
  EXPECT_EQ(rig.scan(), Status::Ok);
}

TEST(Bq79616Scan, PartsCanBeLeftOut) {
  auto config = test::configFor(2);
  config.scanParts = bq::kValidCells;
  ChainRig rig(2, config);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.uart.clearWireLog();
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.count("TX"), 1u);
  EXPECT_EQ(rig.records[1].valid, bq::kValidCells);
}

TEST(Bq79616Scan, SixtyFourDevicesAtMost115PercentOfTheWireMinimum) {
  auto config = test::configFor(64);
  config.scanParts = bq::kValidCells;
  ChainRig rig(64, config);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.uart.clearWireLog();
  const auto frames = rig.chain.stats().commandFrames;
  const uint64_t start = rig.harness.nowUs();
  ASSERT_EQ(rig.scan(), Status::Ok);
  const uint64_t took = rig.harness.nowUs() - start;
  EXPECT_EQ(rig.chain.stats().commandFrames, frames + 1) << "one broadcast read for all 1024 cells";
  // Wire minimum at 1 Mbaud, 10 bits per byte: the 6-byte command plus 64 frames of 32 + 6 bytes.
  const uint64_t wireUs = (6 + 64 * (32 + 6)) * 10;
  const double ratio = static_cast<double>(took) / static_cast<double>(wireUs);
  std::printf("REPORT bq79616.read64.us=%llu wire_min_us=%llu ratio=%.3f\n",
              static_cast<unsigned long long>(took), static_cast<unsigned long long>(wireUs), ratio);
  EXPECT_EQ(wireUs, 24380u);
  EXPECT_LE(ratio, 1.15);
  EXPECT_EQ(rig.summary.validDevices, 64);
  for (uint8_t d = 0; d < 64; ++d)
    ASSERT_EQ(rig.records[d].cellRaw[15], rig.emulator.cellRaw(d, 16)) << int(d);
}

TEST(Bq79616Scan, FullScanOf64DevicesReportsItsBusTime) {
  ChainRig rig(64);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  const uint64_t start = rig.harness.nowUs();
  ASSERT_EQ(rig.scan(), Status::Ok);
  const uint64_t took = rig.harness.nowUs() - start;
  // Cells 38, die temperatures 10, GPIOs 22, FAULT_SUMMARY 7 bytes per device, plus four 6-byte commands.
  const uint64_t wireUs = (4 * 6 + 64 * (38 + 10 + 22 + 7)) * 10;
  std::printf("REPORT bq79616.scan64.us=%llu wire_min_us=%llu ratio=%.3f\n",
              static_cast<unsigned long long>(took), static_cast<unsigned long long>(wireUs),
              static_cast<double>(took) / static_cast<double>(wireUs));
  EXPECT_LE(took, wireUs * 115 / 100);
}

TEST(Bq79616Scan, NothingStartsWhileBusyOrBeforeBringUp) {
  ChainRig rig(2);
  rig.records.resize(2);
  EXPECT_EQ(rig.chain.startScan(rig.records, rig.summary), Status::NotReady);
  ASSERT_EQ(rig.chain.startBringUp(), Status::Ok);
  EXPECT_EQ(rig.chain.startScan(rig.records, rig.summary), Status::Busy);
  EXPECT_EQ(rig.chain.startRecovery(), Status::Busy);
  EXPECT_EQ(rig.finish(Status::Ok), Status::Ok);
  std::vector<bq::DeviceRecord> tooFew(1);
  EXPECT_EQ(rig.chain.startScan(tooFew, rig.summary), Status::InvalidArgument);
}

TEST(Bq79616Scan, LinkStatisticsCountFramesAndNothingElseOnAHealthyLink) {
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  const auto before = rig.chain.stats();
  for (int i = 0; i < 10; ++i)
    ASSERT_EQ(rig.scan(), Status::Ok);
  const auto& s = rig.chain.stats();
  EXPECT_EQ(s.commandFrames - before.commandFrames, 40u);
  EXPECT_EQ(s.responseFrames - before.responseFrames, 160u);
  EXPECT_EQ(s.retries, 0u);
  EXPECT_EQ(s.crcErrors(), 0u);
  EXPECT_EQ(s.timeouts(), 0u);
  EXPECT_EQ(s.localisations, 0u);
}

}  // namespace
