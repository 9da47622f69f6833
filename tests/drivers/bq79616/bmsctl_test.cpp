// `bmsctl trace bq79616` as a user runs it: the built binary, its stdout and exit status (README "Host tools"
// "Host tools" contract). Every frame TI prints in SLUUC56B / SLUAA17A must come out byte for byte.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "support/tool_run.hpp"
#include "ti_vectors.hpp"

#ifndef BMSCTL_PATH
#error "BMSCTL_PATH must name the bmsctl binary"
#endif

namespace {

using test::ToolRun;

ToolRun bmsctl(const std::string& args) {
  return test::runTool(std::string(BMSCTL_PATH) + " trace bq79616 " + args);
}

TEST(Bq79616Bmsctl, EverySection3FrameIsTracedByteExact) {
  for (const auto& v : test::tiVectors()) {
    const ToolRun run = bmsctl(v.args);
    EXPECT_EQ(run.status, 0) << v.args << "\n" << run.err;
    const auto tx = run.lines("TX ");
    ASSERT_EQ(tx.size(), 1u) << v.args;
    EXPECT_EQ(tx[0], test::hexLine("TX", v.bytes)) << v.what << " (bmsctl trace bq79616 " << v.args << ")";
  }
}

TEST(Bq79616Bmsctl, SendWakeExampleFromTheBrief) {
  const ToolRun run = bmsctl("write single 0 0x309 20");
  EXPECT_EQ(run.status, 0);
  ASSERT_FALSE(run.out.empty());
  EXPECT_EQ(run.out[0], "TX 90 00 03 09 20 13 95");
  EXPECT_TRUE(run.has("# write: Ok"));
}

TEST(Bq79616Bmsctl, WakeRunsTheDriversStateMachine) {
  const ToolRun run = bmsctl("--devices 3 wake");
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_GE(run.out.size(), 4u);
  EXPECT_EQ(run.out[0], "PING WAKE 2250us");
  EXPECT_EQ(run.out[1], "PING WAKE 2250us");
  EXPECT_EQ(run.out[2], "TX 90 00 03 09 20 13 95");
  EXPECT_EQ(run.out[3].rfind("# wake: Ok", 0), 0u) << run.out[3];
}

TEST(Bq79616Bmsctl, AutoaddressTracesTiSequenceAndTheReadBack) {
  const ToolRun run = bmsctl("autoaddress");  // --devices defaults to 2
  EXPECT_EQ(run.status, 0) << run.err;
  const auto tx = run.lines("TX ");
  ASSERT_EQ(tx.size(), 28u);
  EXPECT_EQ(tx[8], "TX D0 03 09 01 0F 74");
  EXPECT_EQ(tx[9], "TX D0 03 06 00 CB 44");
  EXPECT_EQ(tx[10], "TX D0 03 06 01 0A 84");
  EXPECT_EQ(tx[12], "TX D0 03 08 02 4E E5");
  EXPECT_EQ(tx[13], "TX 90 00 03 08 00 13 DD");
  EXPECT_EQ(tx[14], "TX 90 01 03 08 03 52 20");
  EXPECT_EQ(tx[15], "TX C0 03 43 00 FD 14");
  EXPECT_EQ(tx[23], "TX D0 03 32 03 9D 85");
  EXPECT_EQ(tx[25], "TX 80 01 03 06 00 D7 82");
  EXPECT_TRUE(run.has("PING") == false);
  ASSERT_FALSE(run.out.empty());
  EXPECT_EQ(run.out.back().rfind("# autoaddress: Ok", 0), 0u) << run.out.back();
}

TEST(Bq79616Bmsctl, ReadsAcceptGeneratedNamesAndDecodeEachDevice) {
  const ToolRun run = bmsctl("read broadcast vcell16_hi 32");
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_EQ(run.lines("TX ").size(), 1u);
  EXPECT_EQ(run.lines("TX ")[0], "TX C0 05 68 1F 42 2D");
  ASSERT_EQ(run.lines("RX ").size(), 1u);
  EXPECT_EQ(run.lines("RX ")[0].size(), 2u + 3 * 2 * 38) << "two frames of 38 bytes";
  // The emulator's default for device 1, cell 16: 3.6 V + 1 mV + 1.6 mV -> code 18888 (0x49C8).
  EXPECT_TRUE(run.has("# dev 1 Vcell16 = 0x49C8 = 3602.5 mV"));
  EXPECT_EQ(run.lines("# dev 1 Vcell").size(), 16u);
  EXPECT_EQ(run.lines("# dev 0 Vcell").size(), 16u);
  EXPECT_TRUE(run.has("# read: Ok, 2 of 2 frames"));
}

TEST(Bq79616Bmsctl, SingleReadOfAnAddressShowsTheResponseFrame) {
  const ToolRun run = bmsctl("read single 1 Dir0Addr 1");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.lines("TX ")[0], "TX 80 01 03 06 00 D7 82");
  ASSERT_EQ(run.lines("RX ").size(), 1u);
  EXPECT_EQ(run.lines("RX ")[0].substr(0, 17), "RX 00 01 03 06 01");
  EXPECT_TRUE(run.has("# dev 1 Dir0Addr = 0x01"));
}

TEST(Bq79616Bmsctl, AReadOfAMissingDeviceFailsWithStatusOne) {
  const ToolRun run = bmsctl("--devices 2 read single 5 0x306 1");
  EXPECT_EQ(run.status, 1);
  EXPECT_TRUE(run.has("RX NoResponse after 0 bytes"));
}

TEST(Bq79616Bmsctl, BadArgumentsAreUsageErrors) {
  const std::vector<std::string> bad = {
      "read bogus 0x306 1",
      "read single 64 0x306 1",
      "read broadcast 0x568 129",
      "read broadcast 0x568 0",
      "read broadcast NoSuchReg 1",
      "read broadcast 0x306",
      "read single 1 0x306 1 2",
      "write broadcast 0x309",
      "write broadcast 0x309 1 2 3 4 5 6 7 8 9",
      "write broadcast 0x309 XYZ",
      "write single 0x309 20",
      "--devices 65 wake",
      "--devices 0 wake",
      "--devices x wake",
      "frobnicate",
      "wake now",
      "--crc wake",
      "--devices 1 read stack 0x306 1",
  };
  for (const auto& args : bad) {
    const ToolRun run = bmsctl(args);
    EXPECT_EQ(run.status, 2) << args;
    EXPECT_TRUE(run.out.empty()) << args << ": a usage error prints nothing on stdout";
    EXPECT_EQ(run.err.rfind("bmsctl: error: ", 0), 0u) << args << ": " << run.err;
  }
}

// Issue 12: `app-start` is the application's own start-up, reviewable line by line against TI's sequence:
// the wake, TI's auto-addressing, the CRC refresh in TI's order, the ADC start, then the first scan.
TEST(Bq79616Bmsctl, AppStartTracesTheApplicationFromResetToItsFirstScan) {
  const ToolRun run = bmsctl("app-start");  // --devices defaults to 2, as the image
  ASSERT_EQ(run.status, 0) << run.err;
  std::vector<std::string> wire;
  for (const auto& l : run.out)
    if (l.rfind("TX ", 0) == 0 || l.rfind("PING ", 0) == 0) wire.push_back(l);
  ASSERT_GE(wire.size(), 3u);
  EXPECT_EQ(wire[0], "PING WAKE 2250us");
  EXPECT_EQ(wire[1], "PING WAKE 2250us");
  EXPECT_EQ(wire[2], "TX 90 00 03 09 20 13 95");
  // TI's frames (SLUUC56B / SLUAA17A), in the order the application must send them.
  const std::vector<std::string> order = {
      "TX D0 03 09 01 0F 74",     // CONTROL1 = ADDR_WR
      "TX D0 03 08 02 4E E5",     // COMM_CTRL = stack
      "TX D0 03 32 03 9D 85",     // FAULT_RST2: the start-up comm faults
      "TX D0 00 17 40 36 E4",     // FAULT_MSK2 = MSK_OTP_CRC
      "TX D0 00 03 0A B8 13",     // ACTIVE_CELL = 16
      "TX D0 00 07 02 BB 15",     // ADC_CONF1 = 26 Hz LPF
      "TX C0 05 0C 01 E8 E5",     // CUST_CRC_RSLT
      "TX D1 03 31 FF FF 88 29",  // FAULT_RST1/2
      "TX D0 03 0D 0E 4D B0",     // ADC_CTRL1 = continuous, LPF, MAIN_GO
      "TX C0 05 68 1F 42 2D",     // the first scan's cells
  };
  size_t at = 0;
  for (const auto& want : order) {
    while (at < wire.size() && wire[at] != want)
      ++at;
    EXPECT_LT(at, wire.size()) << "missing or out of order: " << want;
  }
  EXPECT_EQ(run.out.back().rfind("# app-start: first complete scan at ", 0), 0u) << run.out.back();
  EXPECT_NE(run.out.back().find("2 of 2 devices valid"), std::string::npos) << run.out.back();
}

TEST(Bq79616Bmsctl, AppStartRunsSixtyFourDevices) {
  const ToolRun run = bmsctl("--devices 64 app-start");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.back().find("64 of 64 devices valid"), std::string::npos) << run.out.back();
  EXPECT_EQ(bmsctl("app-start now").status, 2);
}

}  // namespace
