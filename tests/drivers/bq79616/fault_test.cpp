// Injected faults: each is detected and named (device and Status), recovered where the recovery ladder can,
// and never hangs the scheduler (every operation runs under a virtual-time limit in ChainRig::finish()).
#include <gtest/gtest.h>

#include <string>

#include "chain_rig.hpp"
#include "regmap/bq79616.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
namespace r = fw::regmap::bq79616::reg;
using bq::RecoveryLevel;
using fw::Status;
using test::ChainRig;

constexpr uint8_t kComm = fw::regmap::bq79616::bits::FaultSummary::fault_comm_mask;

void expectZeros(const bq::DeviceRecord& rec) {
  for (int16_t v : rec.cellRaw)
    EXPECT_EQ(v, 0);
  EXPECT_EQ(rec.dieTemp[0], 0);
  EXPECT_EQ(rec.faultSummary, 0);
}

TEST(Bq79616Faults, BrokenLinkAboveDeviceKReportsTheDevicesThatAnswer) {
  ChainRig rig(8);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.breakLinkAbove(4);
  const uint64_t start = rig.harness.nowUs();
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  EXPECT_LT(rig.harness.nowUs() - start, 30000u) << "a broken chain costs a few timeouts, not a hang";
  EXPECT_EQ(rig.summary.firstError.device, 5);
  EXPECT_EQ(rig.summary.firstError.status, Status::NoResponse);
  EXPECT_EQ(rig.summary.validDevices, 5);
  for (uint8_t d = 0; d < 5; ++d) {
    EXPECT_EQ(rig.records[d].status, Status::Ok) << int(d);
    EXPECT_EQ(rig.records[d].cellRaw[0], rig.emulator.cellRaw(d, 1));
  }
  for (uint8_t d = 5; d < 8; ++d) {
    EXPECT_EQ(rig.records[d].status, Status::NoResponse) << int(d);
    EXPECT_EQ(rig.records[d].valid, 0);
    expectZeros(rig.records[d]);
  }
  EXPECT_GE(rig.chain.stats().localisations, 1u);
  EXPECT_GE(rig.chain.stats().errors[static_cast<int>(Status::NoResponse)], 1u);

  // No rung can mend a broken cable: the ladder ends with the chain re-discovered as 5 devices.
  EXPECT_EQ(rig.finish(rig.chain.startRecovery(), fw::s(10)), Status::CommFault);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::HardwareReset);
  EXPECT_EQ(rig.chain.devices(), 5);
  EXPECT_EQ(rig.chain.lastFault().device, 5);
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  EXPECT_EQ(rig.summary.validDevices, 5);
  EXPECT_EQ(rig.records[6].status, Status::NoResponse);

  rig.emulator.healLink();
  EXPECT_EQ(rig.finish(rig.chain.startRecovery(), fw::s(10)), Status::Ok);
  EXPECT_EQ(rig.chain.devices(), 8);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::Rewake);
  EXPECT_EQ(rig.scan(), Status::Ok);
}

TEST(Bq79616Faults, AMuteDeviceIsNamedAndTheOthersStillMeasured) {
  ChainRig rig(6);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.setMuted(3, true);
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  EXPECT_EQ(rig.summary.firstError.device, 3);
  for (uint8_t d : {0, 1, 2, 4, 5}) {
    EXPECT_EQ(rig.records[d].status, Status::Ok) << int(d);
    EXPECT_EQ(rig.records[d].cellRaw[7], rig.emulator.cellRaw(d, 8)) << int(d);
  }
  EXPECT_EQ(rig.records[3].valid, 0);
  expectZeros(rig.records[3]);
}

TEST(Bq79616Faults, ACorruptedByteIsRetriedAndCounted) {
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  const auto before = rig.chain.stats();
  rig.emulator.corruptResponse(2, 10, 0x04, 1);  // one bit of device 2's next response, on the UART
  EXPECT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.chain.stats().crcErrors() - before.crcErrors(), 1u);
  EXPECT_EQ(rig.chain.stats().retries - before.retries, 1u);
  EXPECT_EQ(rig.records[2].cellRaw[12], rig.emulator.cellRaw(2, 13));
}

TEST(Bq79616Faults, APersistentlyCorruptedDeviceIsNamedWithCrc) {
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.corruptResponse(2, 10, 0x04, 1000);
  EXPECT_EQ(rig.scan(), Status::Crc);
  EXPECT_EQ(rig.summary.firstError.device, 2);
  EXPECT_EQ(rig.summary.firstError.status, Status::Crc);
  EXPECT_EQ(rig.records[2].valid & bq::kValidCells, 0);
  EXPECT_EQ(rig.records[2].cellRaw[12], 0) << "a frame that failed its CRC never becomes a value";
  for (uint8_t d : {0, 1, 3})
    EXPECT_EQ(rig.records[d].status, Status::Ok);
}

TEST(Bq79616Faults, ATruncatedResponseIsRetried) {
  ChainRig rig(3);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  const auto before = rig.chain.stats();
  rig.emulator.truncateNextResponse(2 * 38 + 5);
  EXPECT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.chain.stats().errors[static_cast<int>(Status::Truncated)] -
                before.errors[static_cast<int>(Status::Truncated)],
            1u);
  EXPECT_EQ(rig.chain.stats().retries - before.retries, 1u);
}

TEST(Bq79616Faults, AnswersBeyondWhatWasAskedAreDrainedNotMisread) {
  // Two devices claim TOP_STACK, so the chain sends one frame more than the driver asked for. Its tail must
  // not become the start of the retry's response.
  ChainRig rig(3, test::configFor(2));
  ASSERT_EQ(rig.bringUp(), Status::VerifyFailed);  // the third device was noticed, the chain runs with two
  rig.emulator.setReg(2, r::CommCtrl.address, 0x03);
  const auto before = rig.chain.stats();
  EXPECT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.chain.stats().errors[static_cast<int>(Status::DeviceId)] -
                before.errors[static_cast<int>(Status::DeviceId)],
            8u)
      << "each part: the first frame came from device 2, twice";
  EXPECT_EQ(rig.chain.stats().crcErrors(), before.crcErrors()) << "no stray bytes were read as a frame";
  EXPECT_EQ(rig.records[1].cellRaw[3], rig.emulator.cellRaw(1, 4));
  EXPECT_EQ(rig.records[0].cellRaw[3], rig.emulator.cellRaw(0, 4));
}

struct FaultLineRig : ChainRig {
  explicit FaultLineRig(uint8_t n, bq::ChainConfig config) : ChainRig(n, config) {
    emulator.attachFaultPin(nfault);
    chain.attachFaultLine(nfault, test::kFault);
  }
  explicit FaultLineRig(uint8_t n) : FaultLineRig(n, test::configFor(n)) {}
  bsp::host::SimEdgeInput nfault{harness.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true};
};

TEST(Bq79616Faults, AStickyCommFaultRaisesNfaultIsReadAndCleared) {
  FaultLineRig rig(6);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  EXPECT_FALSE(rig.chain.faultLineActive());
  // The chips flag their own wake-up (FAULT_SYS[DRST]) until bring-up clears it, and the customer CRC for one
  // pass after FAULT_MSK2 is unmasked (it is inside the CRC: chain.hpp): two edges so far.
  EXPECT_EQ(rig.chain.stats().faultLineEdges, 2u);
  const int done = rig.task.done;
  rig.emulator.injectCommFault(4, false);
  rig.harness.runFor(fw::ms(1));
  EXPECT_TRUE(rig.chain.faultLineActive());
  EXPECT_EQ(rig.chain.stats().faultLineEdges, 3u);
  EXPECT_EQ(rig.task.done, done) << "an nFAULT edge ends no operation";
  ASSERT_EQ(rig.scan(), Status::Ok) << "faults are data; the measurements are still valid";
  EXPECT_EQ(rig.records[4].faultSummary, kComm);
  EXPECT_EQ(rig.records[0].faultSummary, kComm) << "the base latched FCOMM_DET";
  EXPECT_EQ(rig.summary.faultedDevices, 2);
  EXPECT_EQ(rig.finish(rig.chain.startClearFaults()), Status::Ok);
  EXPECT_FALSE(rig.chain.faultLineActive());
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.summary.faultedDevices, 0);
  EXPECT_EQ(rig.chain.stats().faultClears, 1u);
}

TEST(Bq79616Faults, AFaultThatKeepsComingBackIsNamedNotHidden) {
  FaultLineRig rig(6);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.injectCommFault(4, true);
  EXPECT_EQ(rig.finish(rig.chain.startClearFaults()), Status::CommFault);
  EXPECT_EQ(rig.chain.lastFault().device, 4) << "the stack device, not the base echoing it";
  EXPECT_TRUE(rig.chain.faultLineActive());
  rig.emulator.endCommFaultCause(4);
  EXPECT_EQ(rig.finish(rig.chain.startClearFaults()), Status::Ok);
  EXPECT_FALSE(rig.chain.faultLineActive());
}

TEST(Bq79616Faults, AnNfaultEdgeMakesTheNextScanReadFaults) {
  auto config = test::configFor(3);
  config.scanParts = bq::kValidCells;
  FaultLineRig rig(3, config);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  ASSERT_EQ(rig.scan(), Status::Ok);  // reads FAULT_SUMMARY once for the wake-up edge during bring-up
  rig.uart.clearWireLog();
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.count("TX"), 1u);
  rig.emulator.injectCommFault(1, false);
  rig.harness.runFor(fw::ms(1));
  rig.uart.clearWireLog();
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.count("TX"), 2u);
  EXPECT_EQ(rig.records[1].faultSummary, kComm);
  rig.uart.clearWireLog();
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.count("TX"), 1u) << "read once per edge";
}

TEST(Bq79616Faults, AStuckBaseReceiverIsRecoveredByCommClear) {
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.desyncBase();
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  EXPECT_EQ(rig.summary.firstError.device, 0);
  rig.uart.clearWireLog();
  EXPECT_EQ(rig.finish(rig.chain.startRecovery()), Status::Ok);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::CommClear);
  EXPECT_EQ(rig.chain.stats().recoveries[0], 1u);
  EXPECT_EQ(rig.count("PING COMM_CLEAR 18us"), 1u);
  EXPECT_EQ(rig.count("PING WAKE"), 0u) << "no reset when a COMM CLEAR was enough";
  EXPECT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.summary.faultedDevices, 0) << "the recovery cleared the COMMCLR_DET it caused";
}

TEST(Bq79616Faults, ASleepingChainIsRecoveredBySleepToActiveWithoutReset) {
  ChainRig rig(5);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.sleepAll();
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  rig.uart.clearWireLog();
  EXPECT_EQ(rig.finish(rig.chain.startRecovery()), Status::Ok);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::SleepToActive);
  EXPECT_EQ(rig.count("PING SLEEPtoACTIVE 275us"), 1u);
  EXPECT_EQ(rig.emulator.reg(4, r::AdcCtrl1.address), 0x0E) << "configuration kept: no WAKE";
  EXPECT_EQ(rig.scan(), Status::Ok);
}

TEST(Bq79616Faults, ADeviceThatLostItsAddressIsRecoveredByRewake) {
  ChainRig rig(5);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.harness.runFor(fw::ms(2));
  rig.emulator.resetDevice(3);
  rig.harness.runFor(fw::ms(2));
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  EXPECT_EQ(rig.summary.firstError.device, 3) << "it no longer answers to its address";
  EXPECT_EQ(rig.records[4].status, Status::Ok) << "the top's frame came through";
  EXPECT_EQ(rig.records[2].status, Status::Ok) << "the ones below it were read one by one";
  EXPECT_EQ(rig.finish(rig.chain.startRecovery()), Status::Ok);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::Rewake);
  for (uint8_t k = 0; k < 5; ++k)
    EXPECT_EQ(rig.emulator.address(k), k);
  EXPECT_EQ(rig.scan(), Status::Ok);
}

TEST(Bq79616Faults, AHungDeviceNeedsTheHardwareReset) {
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.hangDevice(2);
  EXPECT_EQ(rig.scan(), Status::NoResponse);
  rig.uart.clearWireLog();
  EXPECT_EQ(rig.finish(rig.chain.startRecovery(), fw::s(10)), Status::Ok);
  EXPECT_EQ(rig.chain.lastRecovery(), RecoveryLevel::HardwareReset);
  EXPECT_EQ(rig.count("TX 90 00 03 0A 02"), 1u) << "CONTROL2[SEND_HW_RESET] sends the tone up first";
  EXPECT_EQ(rig.count("PING HW_RESET 40000us"), 1u);
  EXPECT_EQ(rig.chain.stats().recoveries[3], 1u);
  EXPECT_EQ(rig.scan(), Status::Ok);
}

// A UART that accepts everything and never completes: the driver's guard timer must take the line back.
class DeadUart final : public fw::hal::Uart {
 public:
  int aborts = 0;

 private:
  fw::Status doStart(fw::hal::UartExchange&, fw::hal::Notify) override { return Status::Ok; }
  fw::Status doPing(fw::Duration, fw::hal::Notify) override { return Status::Ok; }
  void doAbort() override { ++aborts; }
  uint32_t doBaudRate() const override { return 1000000; }
};

TEST(Bq79616Faults, AUartThatNeverCompletesEndsInTimeout) {
  bsp::host::Harness harness;
  DeadUart uart;
  test::DriverTask task;
  bq::Chain chain(uart, harness.clock,
                  fw::drivers::DriverContext{harness.sched, test::kTask, test::kBus, test::kTimer},
                  test::configFor(2));
  task.chain = &chain;
  harness.sched.addTask(test::kTask, task);
  ASSERT_EQ(chain.startBringUp(), Status::Ok);
  ASSERT_TRUE(harness.runUntil([&] { return task.done == 1; }, fw::s(1)));
  EXPECT_EQ(chain.result(), Status::Timeout);
  EXPECT_EQ(uart.aborts, 1);
  EXPECT_LT(harness.nowUs(), 30000u);
  EXPECT_EQ(chain.stats().errors[static_cast<int>(Status::Timeout)], 1u);
}

}  // namespace

namespace {

// Regression: an operation that ended on a failed read other than a scan (here clear-faults' read-back,
// corrupted twice so its retry fails too) left the driver marked as draining, and the next operation
// repeated its first bus step: one raw write went out five times, and a bring-up sent six WAKE pings back to
// back with no setup wait between them. The line is drained once, then each operation runs as written.
TEST(Bq79616Faults, AFailedReadDoesNotRepeatTheNextOperationsFirstStep) {
  namespace r = fw::regmap::bq79616::reg;
  test::ChainRig rig(3);
  ASSERT_EQ(rig.bringUp(), fw::Status::Ok);

  rig.emulator.corruptResponse(1, 4, 0x40, 2);
  ASSERT_EQ(rig.finish(rig.chain.startClearFaults()), fw::Status::Crc);
  rig.uart.clearWireLog();
  const std::vector<uint8_t> zero = {0x00};
  ASSERT_EQ(rig.finish(rig.chain.startWrite(fw::drivers::bq79616::RequestType::BroadcastWrite, 0,
                                            r::OtpEccDatain1.address, zero)),
            fw::Status::Ok);
  size_t writes = 0;
  for (const auto& line : rig.uart.wireLog())
    writes += line.rfind("TX D0 03 43 00", 0) == 0;
  EXPECT_EQ(writes, 1u) << "one write, one frame";

  rig.emulator.corruptResponse(1, 4, 0x40, 2);
  ASSERT_EQ(rig.finish(rig.chain.startClearFaults()), fw::Status::Crc);
  rig.uart.clearWireLog();
  ASSERT_EQ(rig.bringUp(), fw::Status::Ok);
  size_t wakes = 0;
  for (const auto& line : rig.uart.wireLog())
    wakes += line.rfind("PING WAKE", 0) == 0;
  EXPECT_EQ(wakes, 2u) << "bring-up sends its two WAKE pings (the second for a chain shut down), no more";
}

}  // namespace
