// Every fault the emulator can inject, through the driver: never published, counted, recovered (the next
// good read is published). Scans are used where "published" matters: a Measurement is written only by an
// Ok scan, so a sentinel record proves that nothing was published.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "rig.hpp"

namespace bq4050_test {
namespace {

using K = Emu::FaultKind;

// A record no scan of the default emulator can produce: seeing it unchanged proves nothing was published.
bq::Measurement sentinel() {
  bq::Measurement m;
  m.voltageMv = 1;
  m.rsocPercent = 222;
  return m;
}

void expectDefaultPack(const bq::Measurement& m) {
  EXPECT_EQ(m.voltageMv, 15000);
  EXPECT_EQ(m.temperatureDeciK, 2982);
  EXPECT_EQ(m.rsocPercent, 80);
  EXPECT_EQ(m.cellMv[0], 3750);
  EXPECT_EQ(m.cellMv[3], 3750);
}

TEST(Bq4050Fault, AddressNackIsRetriedAfterTheBackoff) {
  Rig rig;
  rig.emu.inject({.kind = K::AddressNack, .times = 2});
  uint16_t v = 0;
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(v, 15000);
  EXPECT_EQ(rig.gauge.stats().count(Status::Nack), 2u);
  EXPECT_EQ(rig.gauge.stats().retries, 2u);
  const auto& log = rig.bus.wireLog();
  EXPECT_EQ(log[0].text, "S 16 NACK P");
  EXPECT_GE(log[1].startUs - log[0].endUs, rig.gauge.config().nackBackoff.us);
}

TEST(Bq4050Fault, GaugeThatNeverAnswersFailsWithNackAfterTheRetries) {
  Rig rig;
  rig.bus.detach(Emu::kAddress);
  bq::Measurement m = sentinel();
  EXPECT_EQ(rig.scan(m), Status::Nack);
  EXPECT_EQ(m.voltageMv, 1);
  EXPECT_EQ(rig.gauge.stats().count(Status::Nack), 1u + rig.gauge.config().retries);
  EXPECT_EQ(rig.gauge.stats().published, 0u);
}

TEST(Bq4050Fault, DataNackIsRetried) {
  Rig rig;
  rig.emu.inject({.kind = K::DataNack, .command = 0x09, .index = 0});
  uint16_t v = 0;
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(rig.wire()[0], "S 16 09 NACK P");
  EXPECT_EQ(rig.gauge.stats().count(Status::DataNack), 1u);
}

TEST(Bq4050Fault, StretchWithinTheBusLimitIsTolerated) {
  Rig rig;  // stretch limit 25 ms
  rig.emu.inject({.kind = K::Stretch, .command = 0x09, .index = 0, .stretch = fw::ms(20)});
  uint16_t v = 0;
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(v, 15000);
  EXPECT_EQ(rig.gauge.stats().count(Status::Timeout), 0u);
  EXPECT_EQ(rig.gauge.stats().retries, 0u);
  EXPECT_GE(rig.bus.busTimeUs(), 20000u);
}

TEST(Bq4050Fault, StretchBeyondTheLimitTimesOutRecoversAndResendsAfterTheFlashWrite) {
  // The family's data-flash erase stretches 40.08 ms (SLUUCA6): the bus gives up at 25 ms, clocks the
  // recovery, and the driver resends only after timeoutBackoff (50 ms), when the erase is over.
  Rig rig;
  rig.emu.inject({.kind = K::Stretch, .command = 0x09, .index = 0, .stretch = fw::ms(40)});
  uint16_t v = 0;
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(v, 15000);
  EXPECT_EQ(rig.gauge.stats().count(Status::Timeout), 1u);
  EXPECT_EQ(rig.bus.recoveries(), 1u);
  EXPECT_EQ(rig.emu.counters().recoveries, 1u);
  const auto& log = rig.bus.wireLog();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].text, "S 16 09 Sr 17 [] TIMEOUT RECOVERY P");
  EXPECT_LT(log[0].endUs - log[0].startUs, 27000u) << "bounded by the 25 ms stretch limit";
  EXPECT_GE(log[1].startUs - log[0].endUs, 50000u);
}

TEST(Bq4050Fault, StretchOnTheCommandByteBeyondTheLimitIsResentWholeAndCounted) {
  Rig rig;
  rig.emu.inject({.kind = K::Stretch, .command = 0x44, .index = 0, .stretch = fw::ms(30), .onRead = false});
  std::array<uint8_t, 4> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0051, out, length)), Status::Ok);
  EXPECT_EQ(rig.gauge.stats().count(Status::Timeout), 1u);
  // The MAC command itself timed out, so it was sent again before the result was read.
  EXPECT_EQ(rig.wire().size(), 3u);
  EXPECT_EQ(rig.wire()[0], "S 16 44 TIMEOUT RECOVERY P");
  EXPECT_EQ(rig.emu.macLog(), (std::vector<uint16_t>{0x0051}));
}

TEST(Bq4050Fault, CorruptedByteWithPecIsCountedAndNeverPublished) {
  Rig rig;
  rig.emu.inject({.kind = K::CorruptByte, .command = 0x09, .index = 0, .value = 0x01});
  bq::Measurement m = sentinel();
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_EQ(m.voltageMv, 15000) << "the corrupted 14999 never reached the record";
  EXPECT_EQ(rig.gauge.stats().pecErrors(), 1u);
  EXPECT_EQ(rig.wire()[0], "S 16 09 Sr 17 [99 3A 84] P") << "low byte 98 -> 99, PEC of the true bytes";
}

TEST(Bq4050Fault, CorruptedPlausibleByteWithoutPecIsCaughtByTheConfirmingRead) {
  Rig rig(config(bq::PecMode::Off));
  rig.emu.inject({.kind = K::CorruptByte, .command = 0x09, .index = 0, .value = 0x01});
  uint16_t v = 0;
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(v, 15000);
  EXPECT_EQ(rig.wire(), (std::vector<std::string>{"S 16 09 Sr 17 [99 3A] P", "S 16 09 Sr 17 [98 3A] P",
                                                  "S 16 09 Sr 17 [98 3A] P"}));
  EXPECT_EQ(rig.gauge.stats().disagreements(), 1u);
}

TEST(Bq4050Fault, ReadsThatNeverAgreeFailWithVerifyFailed) {
  Rig rig(config(bq::PecMode::Off));
  for (uint8_t mask : {0x01, 0x02, 0x04, 0x08, 0x10})
    rig.emu.inject({.kind = K::CorruptByte, .command = 0x09, .index = 0, .value = mask});
  uint16_t v = 0x1234;
  EXPECT_EQ(rig.readWord(0x09, v), Status::VerifyFailed);
  EXPECT_EQ(v, 0x1234);
  EXPECT_EQ(rig.gauge.stats().disagreements(), 1u + rig.gauge.config().retries);
}

// Seed 003: the gauge's second byte arrives with its top bit stuck high (voltage 0x3A98 -> 0xBA98).
TEST(Bq4050Fault, Seed003SecondByteTopBitStuckHighIsNeverPublished) {
  for (bq::PecMode pec : {bq::PecMode::On, bq::PecMode::Off}) {
    SCOPED_TRACE(pec == bq::PecMode::On ? "with PEC" : "without PEC");
    Rig rig(config(pec));
    rig.emu.inject({.kind = K::TopBitStuck, .command = 0x09});
    bq::Measurement m = sentinel();
    ASSERT_EQ(rig.scan(m), Status::Ok);
    EXPECT_EQ(m.voltageMv, 15000);
    EXPECT_EQ(rig.wire()[0].rfind("S 16 09 Sr 17 [98 BA", 0), 0u) << rig.wire()[0];
    // Counted: a PEC error with PEC, an implausible 47768 mV (> 20000) without.
    EXPECT_EQ(rig.gauge.stats().count(pec == bq::PecMode::On ? Status::Pec : Status::Implausible), 1u);
    EXPECT_EQ(rig.gauge.stats().published, 1u);
  }
}

TEST(Bq4050Fault, Seed003TopBitStuckOnAValueWithoutRangeIsCaughtByTheRereadWithoutPec) {
  // Current has no range to violate (+500 mA -> -32268 mA is a legal I2): only the re-read catches it.
  Rig rig(config(bq::PecMode::Off));
  rig.emu.setCurrent(500);
  rig.emu.inject({.kind = K::TopBitStuck, .command = 0x0A});
  bq::Measurement m = sentinel();
  ASSERT_EQ(rig.scan(m), Status::Ok);
  EXPECT_EQ(m.currentMa, 500);
  EXPECT_EQ(rig.gauge.stats().disagreements(), 1u);
}

TEST(Bq4050Fault, Seed003AllOnesWordIsNeverPublished) {
  for (bq::PecMode pec : {bq::PecMode::On, bq::PecMode::Off}) {
    SCOPED_TRACE(pec == bq::PecMode::On ? "with PEC" : "without PEC");
    Rig rig(config(pec));
    rig.emu.inject({.kind = K::AllOnes, .command = 0x0D, .times = 2});  // RSOC 80 % -> 0xFFFF, twice
    bq::Measurement m = sentinel();
    ASSERT_EQ(rig.scan(m), Status::Ok);
    EXPECT_EQ(m.rsocPercent, 80);
    EXPECT_EQ(rig.gauge.stats().count(pec == bq::PecMode::On ? Status::Pec : Status::Implausible), 2u);
  }
}

TEST(Bq4050Fault, AsleepGaugeAnswering0xFFWithABadPecIsCountedAndRecovered) {
  Rig rig;
  rig.emu.inject({.kind = K::Asleep, .times = 2});
  bq::Measurement m = sentinel();
  ASSERT_EQ(rig.scan(m), Status::Ok);
  expectDefaultPack(m);
  EXPECT_EQ(rig.wire()[0], "S 16 09 Sr 17 [FF FF FF] P");
  EXPECT_NE(referenceCrc8({0x16, 0x09, 0x17, 0xFF, 0xFF}), 0xFF) << "so the all-ones PEC is a bad one";
  EXPECT_EQ(rig.gauge.stats().pecErrors(), 2u);
}

TEST(Bq4050Fault, AsleepGaugeWithoutPecIsRejectedByRangeAndBlockCount) {
  Rig rig(config(bq::PecMode::Off));
  rig.emu.inject({.kind = K::Asleep, .command = 0x09});
  rig.emu.inject({.kind = K::Asleep, .command = 0x44});  // the MAC result: count 0xFF
  bq::Measurement m = sentinel();
  ASSERT_EQ(rig.scan(m), Status::Ok);
  expectDefaultPack(m);
  EXPECT_EQ(rig.gauge.stats().rejected(), 1u) << "65535 mV is implausible";
  EXPECT_EQ(rig.gauge.stats().count(Status::Length), 1u) << "a count of 255 does not fit";
}

TEST(Bq4050Fault, GaugeAsleepForTheWholeScanPublishesNothingThenRecovers) {
  Rig rig;
  rig.emu.inject({.kind = K::Asleep, .times = 1000});
  bq::Measurement m = sentinel();
  EXPECT_EQ(rig.scan(m), Status::Pec);
  EXPECT_EQ(m.voltageMv, 1);
  EXPECT_EQ(m.rsocPercent, 222);
  EXPECT_EQ(rig.gauge.stats().published, 0u);
  EXPECT_EQ(rig.gauge.stats().recoveries, 2u) << "the 2nd and 3rd transport failures clock a recovery";
  const auto w = rig.wire();
  EXPECT_EQ(std::count(w.begin(), w.end(), "RECOVERY"), 2);
  rig.emu.clearFaults();
  ASSERT_EQ(rig.scan(m), Status::Ok);
  expectDefaultPack(m);
  EXPECT_EQ(rig.gauge.stats().published, 1u);
}

TEST(Bq4050Fault, OversizedBlockCountIsRefusedAndRetried) {
  Rig rig;
  rig.emu.inject({.kind = K::BlockCount, .command = 0x44, .value = 0x40});  // 64 > the 35-byte buffer
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0051, out, length)), Status::Ok);
  EXPECT_EQ(length, 4);
  EXPECT_EQ(rig.wire()[1], "S 16 44 Sr 17 [40] NACK P");
  EXPECT_EQ(rig.gauge.stats().count(Status::Length), 1u);
  EXPECT_EQ(rig.emu.macLog(), (std::vector<uint16_t>{0x0051, 0x0051})) << "the retry resends the command";
}

TEST(Bq4050Fault, ShortMacResultForAFixedSizeValueIsALengthError) {
  Rig rig;
  rig.emu.setMacResult(0x0054, {0x06, 0x00});  // OperationStatus must be 4 bytes
  bq::Measurement m = sentinel();
  EXPECT_EQ(rig.scan(m), Status::Length);
  EXPECT_EQ(m.voltageMv, 1);
}

TEST(Bq4050Fault, StaleMacResultAfterADroppedCommandIsAnEchoMismatch) {
  Rig rig;
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0001, out, length)), Status::Ok);  // leaves DeviceType
  rig.emu.inject({.kind = K::DropMacCommand});
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0051, out, length)), Status::Ok);
  EXPECT_EQ(length, 4);
  EXPECT_EQ(rig.gauge.stats().count(Status::EchoMismatch), 1u);
  EXPECT_EQ(rig.wire()[3].rfind("S 16 44 Sr 17 [04 01 00 50 40", 0), 0u) << "the stale DeviceType answer";
}

TEST(Bq4050Fault, GaugeLeftInCalibrationOutputModeNeverPublishesItsStaleData) {
  // A gauge left streaming calibration data (0xF081) answers every MAC read with that block, however valid
  // its PEC. The scan sizes its status reads for 4 data bytes, so the 14-byte block is refused at its count;
  // a read with room for it finds the echo naming 0xF081. Nothing is published until the mode is left.
  Rig rig;
  ASSERT_EQ(rig.finish(rig.gauge.startSendMac(0xF081)), Status::Ok);
  ASSERT_TRUE(rig.emu.calibrationOutput());
  bq::Measurement m = sentinel();
  EXPECT_EQ(rig.scan(m), Status::Length);
  EXPECT_EQ(m.voltageMv, 1);
  EXPECT_EQ(rig.gauge.stats().count(Status::Length), 1u + rig.gauge.config().retries);
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  EXPECT_EQ(rig.finish(rig.gauge.startReadMac(0x0051, out, length)), Status::EchoMismatch);
  EXPECT_EQ(rig.wire().back().rfind("S 16 44 Sr 17 [10 81 F0 ", 0), 0u) << rig.wire().back();
  EXPECT_EQ(rig.gauge.stats().count(Status::EchoMismatch), 1u + rig.gauge.config().retries);
  ASSERT_EQ(rig.finish(rig.gauge.startSendMac(0xF080)), Status::Ok);
  ASSERT_EQ(rig.scan(m), Status::Ok);
  expectDefaultPack(m);
  EXPECT_FALSE(m.operationStatus.cal());
}

TEST(Bq4050Fault, StuckBusIsRecoveredByTheDriver) {
  Rig rig;
  rig.bus.holdSdaLow(-1);  // a target holds SDA until power is cycled
  uint16_t v = 0;
  EXPECT_EQ(rig.readWord(0x09, v), Status::BusStuck);
  EXPECT_GE(rig.gauge.stats().recoveries, 1u);
  const auto w = rig.wire();
  EXPECT_GE(std::count(w.begin(), w.end(), "RECOVERY"), 1) << "the driver called I2cBus::recover()";
  EXPECT_EQ(rig.gauge.stats().count(Status::BusStuck), 1u + rig.gauge.config().retries);
  rig.bus.holdSdaLow(0);
  ASSERT_EQ(rig.readWord(0x09, v), Status::Ok);
  EXPECT_EQ(v, 15000);
}

// A bus whose completion never comes: the guard ends the operation, and the driver stays busy until the
// late completion frees the buffers it lent.
class SilentBus final : public fw::hal::I2cBus {
 public:
  fw::hal::Notify done;
  fw::hal::I2cTransaction* txn = nullptr;
  int recovers = 0;

 private:
  fw::Status doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& d) override {
    txn = list.data();
    done = d;
    return fw::Status::Ok;
  }
  fw::Status doRecover() override {
    ++recovers;
    return fw::Status::Ok;
  }
  uint32_t doBitRate() const override { return 100000; }
};

TEST(Bq4050Fault, LostBusCompletionIsBoundedByTheGuard) {
  bsp::host::Harness harness;
  SilentBus bus;
  DriverTask task;
  bq::Gauge gauge(bus, harness.clock, fw::drivers::DriverContext{harness.sched, kTask, kBus, kTimer},
                  config(bq::PecMode::On));
  task.gauge = &gauge;
  harness.sched.addTask(kTask, task);
  uint16_t v = 0;
  ASSERT_EQ(gauge.startReadWord(0x09, v), Status::Ok);
  const uint64_t t0 = harness.nowUs();
  ASSERT_TRUE(harness.runUntil([&] { return task.done == 1; }, fw::s(2)));
  EXPECT_EQ(gauge.result(), Status::Timeout);
  EXPECT_LE(harness.nowUs() - t0, gauge.config().busGuard.us + 1000);
  EXPECT_TRUE(gauge.busy()) << "the bus still owns the driver's buffers";
  EXPECT_EQ(gauge.startReadWord(0x09, v), Status::Busy);
  bus.txn->status = Status::Ok;
  bus.done();  // the late completion
  harness.runFor(fw::ms(1));
  EXPECT_FALSE(gauge.busy());
  EXPECT_EQ(task.done, 1) << "the late completion ends nothing";
}

}  // namespace
}  // namespace bq4050_test
