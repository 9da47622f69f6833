// `bmsctl trace bq79616` as a user runs it: the built binary, its stdout and exit status (ARCHITECTURE.md
// "Host tools" contract). Every frame of bq79616-protocol.md section 3 must come out byte for byte.
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

}  // namespace
