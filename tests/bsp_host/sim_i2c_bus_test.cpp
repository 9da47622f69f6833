// The simulated I2C/SMBus controller: wire log in the bmsctl contract format, statuses, timing, PEC.
#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "core/crc.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"

namespace {

using bsp::host::I2cReply;
using fw::Status;

// A scripted target: ACKs everything unless told otherwise, answers reads from a queue.
struct ScriptTarget final : bsp::host::I2cTarget {
  std::deque<uint8_t> replies;
  std::vector<uint8_t> written;
  bool nackAddress = false;
  int nackAfterBytes = -1;
  fw::Duration stretchOnRead{};
  int stops = 0, recoveries = 0;
  I2cReply onStart(bool) override { return {!nackAddress, {}}; }
  I2cReply onWrite(uint8_t b) override {
    written.push_back(b);
    return {nackAfterBytes < 0 || static_cast<int>(written.size()) <= nackAfterBytes, {}};
  }
  uint8_t onRead(fw::Duration& stretch) override {
    stretch = stretchOnRead;
    if (replies.empty()) return 0xFF;
    const uint8_t b = replies.front();
    replies.pop_front();
    return b;
  }
  void onStop() override { ++stops; }
  void onBusRecovery() override { ++recoveries; }
};

struct Fixture {
  bsp::host::Harness h;
  bsp::host::SimI2cBus bus{h.clock, h.irq, {400000, fw::ms(20), fw::us(4)}};
  ScriptTarget target;
  bool done = false;
  Fixture() { bus.attach(0x08, target); }
  Status run(std::vector<fw::hal::I2cTransaction>& list) {
    done = false;
    const Status s =
        bus.start(list, fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done});
    if (s != Status::Ok) return s;
    h.runUntil([&] { return done; }, fw::s(1));
    return list.back().status;
  }
};

TEST(SimI2cBus, WriteReadWithRepeatedStartInContractFormat) {
  Fixture f;
  f.target.replies = {0x68, 0x33, 0x0B, 0x31};
  uint8_t cmd = 0x14, rx[4] = {};
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&cmd, 1}, rx}};
  EXPECT_EQ(f.run(list), Status::Ok);
  ASSERT_EQ(f.bus.wireLog().size(), 1u);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 10 14 Sr 11 [68 33 0B 31] P");  // README "Host tools" example
  EXPECT_EQ(list[0].readCount, 4);
  EXPECT_EQ(rx[3], 0x31);
}

TEST(SimI2cBus, WriteOnlyAndWireTimeAt400kHz) {
  Fixture f;
  const uint8_t bytes[] = {0x3E, 0x22, 0x00};
  std::vector<fw::hal::I2cTransaction> list{{0x08, bytes, {}}};
  const uint64_t t0 = f.h.nowUs();
  EXPECT_EQ(f.run(list), Status::Ok);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 10 3E 22 00 P");
  // START + 4 bytes x 9 bits + STOP = 38 bit times of 2.5 us = 95 us, plus tBUF 1.3 us.
  EXPECT_EQ(f.bus.busTimeUs(), 95u);
  EXPECT_EQ(f.h.nowUs() - t0, 97u);
  EXPECT_EQ(f.target.written, (std::vector<uint8_t>{0x3E, 0x22, 0x00}));
}

TEST(SimI2cBus, AddressNackStopsTheListAndAbortsTheRest) {
  Fixture f;
  f.target.nackAddress = true;
  const uint8_t a = 0x3E, b = 0x40;
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&a, 1}, {}}, {0x08, {&b, 1}, {}}};
  EXPECT_EQ(f.run(list), Status::Aborted);  // run() returns the last transaction's status
  EXPECT_EQ(list[0].status, Status::Nack);
  EXPECT_EQ(list[1].status, Status::Aborted);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 10 NACK P");
  EXPECT_EQ(f.bus.wireLog().size(), 1u);
}

TEST(SimI2cBus, AbsentTargetIsANack) {
  Fixture f;
  const uint8_t a = 0x09;
  std::vector<fw::hal::I2cTransaction> list{{0x0B, {&a, 1}, {}}};
  EXPECT_EQ(f.run(list), Status::Nack);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 16 NACK P");
}

TEST(SimI2cBus, DataNack) {
  Fixture f;
  f.target.nackAfterBytes = 1;
  const uint8_t bytes[] = {0x3E, 0x22};
  std::vector<fw::hal::I2cTransaction> list{{0x08, bytes, {}}};
  EXPECT_EQ(f.run(list), Status::DataNack);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 10 3E 22 NACK P");
}

TEST(SimI2cBus, StretchBeyondTheLimitTimesOutAndRecoversTheBus) {
  Fixture f;
  f.target.stretchOnRead = fw::ms(30);
  uint8_t cmd = 0x14, rx[2];
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&cmd, 1}, rx}};
  const uint64_t t0 = f.h.nowUs();
  EXPECT_EQ(f.run(list), Status::Timeout);
  EXPECT_EQ(f.bus.wireLog()[0].text, "S 10 14 Sr 11 [] TIMEOUT RECOVERY P");
  EXPECT_EQ(f.target.recoveries, 1);
  EXPECT_LT(f.h.nowUs() - t0, 21000u) << "bounded by the stretch limit, not the device";
  EXPECT_EQ(f.bus.recoveries(), 1u);
}

TEST(SimI2cBus, StretchWithinTheLimitIsFine) {
  Fixture f;
  f.target.stretchOnRead = fw::ms(5);
  f.target.replies = {0x01, 0x02};
  uint8_t cmd = 0x14, rx[2];
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&cmd, 1}, rx}};
  EXPECT_EQ(f.run(list), Status::Ok);
  EXPECT_GT(f.bus.busTimeUs(), 10000u);
}

TEST(SimI2cBus, PecAppendedToWritesAndCheckedOnReads) {
  Fixture f;
  f.bus.attach(0x0B, f.target);
  const uint8_t word[] = {0x00, 0x01, 0x00};
  std::vector<fw::hal::I2cTransaction> w{{0x0B, word, {}, true}};
  EXPECT_EQ(f.run(w), Status::Ok);
  const uint8_t onWire[] = {0x16, 0x00, 0x01, 0x00};
  EXPECT_EQ(f.target.written.back(), fw::crc::crc8(onWire, sizeof onWire));

  // Read word 0x09 = 0x3A98 (15000 mV) with the PEC the gauge would send.
  const uint8_t readBytes[] = {0x16, 0x09, 0x17, 0x98, 0x3A};
  const uint8_t pec = fw::crc::crc8(readBytes, sizeof readBytes);
  f.target.replies = {0x98, 0x3A, pec};
  uint8_t cmd = 0x09, rx[2];
  std::vector<fw::hal::I2cTransaction> r{{0x0B, {&cmd, 1}, rx, true}};
  EXPECT_EQ(f.run(r), Status::Ok);
  f.target.replies = {0x98, 0xBA, pec};  // seed 003: the second byte's top bit stuck high
  EXPECT_EQ(f.run(r), Status::Pec);
}

TEST(SimI2cBus, BlockReadFollowsTheCountByteAndRefusesAnOversizedCount) {
  Fixture f;
  f.target.replies = {0x03, 0xAA, 0xBB, 0xCC};
  uint8_t cmd = 0x20, rx[8] = {};
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&cmd, 1}, rx, false, true}};
  EXPECT_EQ(f.run(list), Status::Ok);
  EXPECT_EQ(list[0].readCount, 4);
  EXPECT_EQ(f.bus.wireLog().back().text, "S 10 20 Sr 11 [03 AA BB CC] P");

  f.target.replies = {0x20, 0x01};  // 32 bytes announced, 7 fit
  EXPECT_EQ(f.run(list), Status::Length);
  EXPECT_EQ(list[0].readCount, 1);
  EXPECT_EQ(f.bus.wireLog().back().text, "S 10 20 Sr 11 [20] NACK P");
}

TEST(SimI2cBus, BusyWhileAListRunsAndInvalidArguments) {
  Fixture f;
  const uint8_t a = 1;
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&a, 1}, {}}};
  ASSERT_EQ(f.bus.start(list, {}), Status::Ok);
  EXPECT_EQ(f.bus.start(list, {}), Status::Busy);
  f.h.runFor(fw::ms(1));
  std::vector<fw::hal::I2cTransaction> empty;
  EXPECT_EQ(f.bus.start(empty, {}), Status::InvalidArgument);
  std::vector<fw::hal::I2cTransaction> nothing{{0x08, {}, {}}};
  EXPECT_EQ(f.bus.start(nothing, {}), Status::InvalidArgument);
}

TEST(SimI2cBus, StuckBusIsReportedWhenRecoveryCannotFreeIt) {
  Fixture f;
  f.bus.holdSdaLow(-1);
  const uint8_t a = 1;
  std::vector<fw::hal::I2cTransaction> list{{0x08, {&a, 1}, {}}};
  EXPECT_EQ(f.run(list), Status::BusStuck);
  f.bus.holdSdaLow(3);  // released after three recovery clocks
  EXPECT_EQ(f.run(list), Status::Timeout);
  EXPECT_EQ(f.run(list), Status::Ok);
}

}  // namespace
