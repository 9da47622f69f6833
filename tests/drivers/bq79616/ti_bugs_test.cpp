// The defects of TI's bq79616_uart_to_can example (TI mspm0-sdk 2.09, examples/.../bq79616_uart_to_can, read
// against SLUSE81E), each turned into a test this driver must pass.
#include <gtest/gtest.h>

#include "chain_rig.hpp"
#include "drivers/bq79616/registers.hpp"
#include "regmap/bq79616.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
namespace r = fw::regmap::bq79616::reg;
using bq::RequestType;
using fw::Status;
using test::ChainRig;

// TI: CRC_CHECK_ENABLE is false, so a corrupted response becomes a cell voltage.
TEST(Bq79616TiBugs, ResponseCrcIsAlwaysChecked) {
  ChainRig rig(2);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.corruptResponse(1, 4, 0x40, 1000);  // VCELL16_HI of device 1: a plausible-looking value
  EXPECT_EQ(rig.scan(), Status::Crc);
  EXPECT_EQ(rig.records[1].valid & bq::kValidCells, 0);
  EXPECT_EQ(rig.records[1].cellRaw[15], 0);
}

// TI: the UART receive blocks with no timeout: one missing board hangs the MCU for ever.
TEST(Bq79616TiBugs, NoReceiveIsUnbounded) {
  ChainRig rig(2, test::configFor(3));  // configured for 3, only 2 there
  EXPECT_EQ(rig.bringUp(), Status::CommFault);
  std::vector<uint8_t> rx(3 * bq::responseSize(32));
  const uint64_t start = rig.harness.nowUs();
  EXPECT_EQ(rig.finish(rig.chain.startRead(RequestType::SingleRead, 2, r::Vcell16Hi.address, 32, rx)),
            Status::NoResponse);
  EXPECT_EQ(rig.chain.received(), 0u) << "TI's ReadReg reported the expected length even after a timeout";
  EXPECT_LT(rig.harness.nowUs() - start, 2000u);
  EXPECT_FALSE(rig.uart.busy());
}

// TI: a reverse-direction broadcast write of more than one byte got INIT 0xE0 whatever its length.
TEST(Bq79616TiBugs, ReverseBroadcastWriteHasTheRightInitByte) {
  ChainRig rig(2);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.uart.clearWireLog();
  const std::vector<uint8_t> two = {0x00, 0x00};
  ASSERT_EQ(
      rig.finish(rig.chain.startWrite(RequestType::BroadcastWriteReverse, 0, r::OtpEccDatain1.address, two)),
      Status::Ok);
  ASSERT_EQ(rig.uart.wireLog().size(), 1u);
  EXPECT_EQ(rig.uart.wireLog()[0].substr(0, 5), "TX E1");
}

// TI: PrintAllFaults read (39 + 6) x N bytes into a 39 x N buffer.
TEST(Bq79616TiBugs, BuffersHoldSixtyFourDevicesOfThirtyTwoBytesAndReadsThatDoNotFitAreRefused) {
  static_assert(bq::kRxBufferBytes == 64 * (32 + 6));
  ChainRig rig(4);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.uart.clearWireLog();
  std::vector<uint8_t> small(4 * bq::responseSize(32) - 1);
  EXPECT_EQ(rig.chain.startRead(RequestType::BroadcastRead, 0, r::Vcell16Hi.address, 32, small),
            Status::InvalidArgument);
  EXPECT_TRUE(rig.uart.wireLog().empty()) << "nothing is sent for a read that cannot be received";
  EXPECT_FALSE(rig.chain.busy());
}

// TI: ReadFrameReq refused > 128 bytes but ReadReg still waited for a reply.
TEST(Bq79616TiBugs, AnImpossibleReadIsRefusedAtOnceWithoutWaiting) {
  ChainRig rig(1);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.uart.clearWireLog();
  std::vector<uint8_t> rx(1024);
  const uint64_t now = rig.harness.nowUs();
  EXPECT_EQ(rig.chain.startRead(RequestType::SingleRead, 0, r::Vcell16Hi.address, 129, rx),
            Status::InvalidArgument);
  EXPECT_EQ(rig.chain.startRead(RequestType::SingleRead, 0, r::Vcell16Hi.address, 0, rx),
            Status::InvalidArgument);
  EXPECT_EQ(rig.chain.startRead(RequestType::SingleRead, 64, r::Vcell16Hi.address, 1, rx),
            Status::InvalidArgument);
  EXPECT_EQ(rig.chain.startWrite(RequestType::SingleRead, 0, r::Control1.address, std::vector<uint8_t>{1}),
            Status::InvalidArgument);
  EXPECT_EQ(rig.harness.nowUs(), now);
  EXPECT_TRUE(rig.uart.wireLog().empty());
}

// TI: WAKE 2.0 ms and SLEEPtoACTIVE 250 us sit on the bottom edge of their windows.
TEST(Bq79616TiBugs, PingsSitInsideTheirWindowsWithMargin) {
  EXPECT_GE(bq::kWakePing.us * 100, 2000u * 110);  // tHLD_WAKE 2.0..2.5 ms, 10 % margin
  EXPECT_LE(bq::kWakePing.us * 100, 2500u * 90);
  EXPECT_GE(bq::kSleepToActivePing.us * 100, 250u * 105);  // tUART(StA) 250..300 us
  EXPECT_LE(bq::kSleepToActivePing.us * 100, 300u * 95);
  EXPECT_GE(bq::kHwResetPing.us * 100, 36000u * 110);  // tHLD_HWRST >= 36 ms
  EXPECT_GE(bq::kCommClearPing.us * 100, 15u * 110);   // tUART(CLR) 15..20 bit periods at 1 Mbaud
  EXPECT_LE(bq::kCommClearPing.us * 100, 20u * 95);
}

// TI: TOTALBOARDS is a constant never checked against the devices that answer; values of a board that did
// not answer are whatever the buffer held (memset cleared only sizeof(pointer) bytes).
TEST(Bq79616TiBugs, AValueFromAnEarlierScanNeverSurvivesAFailedOne) {
  ChainRig rig(3);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  ASSERT_EQ(rig.scan(), Status::Ok);
  auto records = rig.records;
  ASSERT_NE(records[2].cellRaw[0], 0);
  rig.emulator.breakLinkAbove(1);
  bq::ScanSummary summary;
  ASSERT_EQ(rig.finish(rig.chain.startScan(records, summary)), Status::NoResponse);
  EXPECT_EQ(records[2].valid, 0);
  for (int16_t v : records[2].cellRaw)
    EXPECT_EQ(v, 0);
  EXPECT_EQ(records[2].dieTemp[0], 0);
  EXPECT_EQ(records[1].cellRaw[0], rig.emulator.cellRaw(1, 1));
}

// TI: no FAULT_SUMMARY polling, nFAULT never read, no recovery. Here FAULT_SUMMARY is part of every scan.
TEST(Bq79616TiBugs, FaultSummaryIsReadWithEveryScan) {
  ChainRig rig(2);
  ASSERT_EQ(rig.bringUp(), Status::Ok);
  rig.emulator.setReg(1, r::FaultOv1.address, 0x01);  // device 1: cell OV
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.records[1].faultSummary, fw::regmap::bq79616::bits::FaultSummary::fault_ovuv_mask);
  EXPECT_EQ(rig.summary.faultedDevices, 1);
  EXPECT_EQ(rig.finish(rig.chain.startClearFaults()), Status::Ok);
  ASSERT_EQ(rig.scan(), Status::Ok);
  EXPECT_EQ(rig.summary.faultedDevices, 0);
}

}  // namespace
