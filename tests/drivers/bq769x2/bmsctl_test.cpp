// Runs the built bmsctl binary and checks its output against the contract (README "Host tools") and
// the seeds' wire bytes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/tool_run.hpp"

#ifndef BMSCTL_PATH
#error "BMSCTL_PATH must name the bmsctl binary"
#endif

namespace {

using test::ToolRun;

ToolRun bmsctl(const std::string& args) {
  return test::runTool(std::string(BMSCTL_PATH) + " " + args);
}

// Everything the tool printed, stdout lines then stderr: for failure messages and for what must appear
// nowhere.
std::string printed(const ToolRun& r) {
  std::string s;
  for (const auto& l : r.out)
    s += l + "\n";
  return s + r.err;
}

TEST(Bq769x2Bmsctl, CrcFetEnableIsTheContractLine) {
  const ToolRun o = bmsctl("trace bq76952 --crc subcmd 0x0022");
  EXPECT_EQ(o.status, 0) << printed(o);
  EXPECT_TRUE(o.has("S 10 3E 22 63 00 00 P")) << printed(o);
  EXPECT_TRUE(o.has("# FetEnable (0x0022) sent")) << printed(o);
}

TEST(Bq769x2Bmsctl, ReadByNameDecodesWithUnit) {
  const ToolRun o = bmsctl("trace bq76952 read Cell1Voltage 2");
  EXPECT_EQ(o.status, 0);
  EXPECT_EQ(o.text, "S 10 14 Sr 11 [74 0E] P\n# Cell1Voltage = 3700 mV\n");
  EXPECT_EQ(o.err, "");
  const ToolRun t = bmsctl("trace bq76952 read IntTemperature 2");
  EXPECT_TRUE(t.has("# IntTemperature = 298.2 K")) << printed(t);
}

TEST(Bq769x2Bmsctl, BlockReadDecodesEveryCommandInIt) {
  const ToolRun o = bmsctl("trace bq76952 read 0x14 40");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(o.has("# Cell16Voltage = 3700 mV")) << printed(o);
  EXPECT_TRUE(o.has("# StackVoltage = 5920 userV")) << printed(o);
  EXPECT_TRUE(o.has("# Cc2Current = 7 userA")) << printed(o);
}

TEST(Bq769x2Bmsctl, WriteSubcommandsAndDataMemory) {
  ToolRun o = bmsctl("trace bq76952 write 0x66 82 F0");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(o.has("S 10 66 82 F0 P")) << printed(o);
  o = bmsctl("trace bq76952 subcmd FET_ENABLE");
  ASSERT_FALSE(o.out.empty());
  EXPECT_EQ(o.out[0], "S 10 3E 22 00 P") << printed(o);  // SLUAA11B 2.3
  EXPECT_EQ(o.err, "");
  EXPECT_TRUE(o.has("S 10 3E Sr 11 [22 00] P")) << printed(o);  // the echo: it has run
  EXPECT_TRUE(o.has("# FetEnable (0x0022) sent")) << printed(o);
  o = bmsctl("trace bq76952 subcmd RESET");
  // SLUAA11B 2.4: no echo after a reset.
  EXPECT_EQ(o.text, "S 10 3E 12 00 P\n# Reset (0x0012) sent\n");
  EXPECT_EQ(o.err, "");
  o = bmsctl("trace bq76952 subcmd-read 0x0001");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(o.has("S 10 3E 01 00 P")) << printed(o);
  EXPECT_TRUE(o.has("# DeviceNumber = 0x7695 (30357)")) << printed(o);
  o = bmsctl("trace bq76952 dm-read 0x9261 1");
  EXPECT_TRUE(o.has("S 10 3E 61 92 P")) << printed(o);
  EXPECT_TRUE(o.has("# EnabledProtectionsA = 0x88 (COV SCD)")) << printed(o);
  o = bmsctl("trace bq76952 dm-write 0x9261 8C");
  EXPECT_EQ(o.status, 0) << printed(o);
  EXPECT_TRUE(o.has("S 10 3E 90 00 P")) << printed(o);
  EXPECT_TRUE(o.has("S 10 3E 61 92 8C P")) << printed(o);
  EXPECT_TRUE(o.has("S 10 60 80 05 P")) << printed(o);
  EXPECT_TRUE(o.has("S 10 3E 92 00 P")) << printed(o);
  o = bmsctl("trace bq76952 dm-write EnabledProtectionsA 88");  // already the value: no CONFIG_UPDATE
  EXPECT_EQ(printed(o).find("3E 90 00"), std::string::npos) << printed(o);
}

TEST(Bq769x2Bmsctl, Bq7690xDevices) {
  ToolRun o = bmsctl("trace bq76907 --crc read 0x14 2");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(o.has("# Cell1Voltage = 3089 mV")) << printed(o);
  o = bmsctl("trace bq76905 subcmd-read DEVICE_NUMBER");
  EXPECT_TRUE(o.has("# DeviceNumber = 0x7605 (30213)")) << printed(o);
  o = bmsctl("trace bq76905 dm-write 0x9024 E1");
  EXPECT_TRUE(o.has("S 10 3E 24 90 E1 P")) << printed(o);
  EXPECT_TRUE(o.has("S 10 60 6A 05 P")) << printed(o);
}

TEST(Bq769x2Bmsctl, FailedOperationPrintsTheTraceAndTheStatus) {
  ToolRun o = bmsctl("trace bq76952 --address=0x10 read 0x14 2");
  EXPECT_EQ(o.status, 1);
  EXPECT_TRUE(o.has("S 20 NACK P")) << printed(o);
  EXPECT_TRUE(o.has("# error: Nack")) << printed(o);
  o = bmsctl("trace bq76952 --fault=nack-always subcmd-read 0x0001");
  EXPECT_EQ(o.status, 1);
  EXPECT_TRUE(o.has("# error: Nack")) << printed(o);
  o = bmsctl("trace bq76952 --fault=checksum subcmd-read 0x0001");  // one fault: the retry succeeds
  EXPECT_EQ(o.status, 0) << printed(o);
}

TEST(Bq769x2Bmsctl, BadArgumentsExitTwoWithoutTouchingTheBus) {
  for (const char* args :
       {"trace bq76952 read Nope 2", "trace bq76952 read 0x14", "trace bq76952 read 0x14 99",
        "trace bq76952 frobnicate 0x14", "trace bq76952 --pec read 0x14 2", "trace bq76952 write 0x66 XYZ",
        "trace bq76952 dm-read Cell1Voltage 2", "trace bq76952 --fault=gremlins subcmd 0x22",
        "trace bq76952 app-start now", "trace bq76907 --crc app-start"}) {
    const ToolRun o = bmsctl(args);
    EXPECT_EQ(o.status, 2) << args << "\n" << printed(o);
    EXPECT_NE(o.err.find("bmsctl: error:"), std::string::npos) << args;
    EXPECT_EQ(printed(o).find("S 10"), std::string::npos) << args;
  }
}

// Each prefix starts a printed line, and the first such lines come in the order given.
void expectInOrder(const ToolRun& o, const std::vector<std::string>& prefixes) {
  long previous = -1;
  for (const auto& p : prefixes) {
    long found = -1;
    for (size_t i = 0; i < o.out.size() && found < 0; ++i) {
      if (o.out[i].rfind(p, 0) == 0) found = static_cast<long>(i);
    }
    ASSERT_GE(found, 0) << "no line " << p << "\n" << printed(o);
    EXPECT_LT(previous, found) << p << " out of order\n" << printed(o);
    previous = found;
  }
}

// app-start prints what the application sends from reset to its first complete scan (issue 12): on the
// BQ76952 the ALERT Pin Config write (0x92FC <- 0x82) inside CONFIG_UPDATE, then FET_ENABLE, SLEEP_DISABLE
// and Alarm Enable, then the scan's four reads. Balancing (issue 28): Balancing Configuration (0x9335)
// compared, Cell Balance Max Cells (0x933A) written with 4 and its checksum and length.
TEST(Bq769x2Bmsctl, AppStartShowsTheStartUpSequence) {
  const ToolRun o = bmsctl("trace bq76952 app-start");
  ASSERT_EQ(o.status, 0) << printed(o);
  expectInOrder(o, {"S 10 3E 01 00 P", "S 10 3E 35 93 P", "S 10 3E 90 00 P", "S 10 3E FC 92 82 P",
                    "S 10 60 EF 05 P", "S 10 3E 3A 93 04 P", "S 10 60 2E 05 P", "S 10 3E 92 00 P",
                    "S 10 3E 22 00 P", "S 10 3E 9A 00 P", "S 10 66 00 F8 P", "S 10 0A Sr 11 [",
                    "S 10 62 Sr 11 [", "S 10 02 Sr 11 [", "S 10 7F Sr 11 [", "# first complete scan at "});
  EXPECT_EQ(o.out.back().rfind("# first complete scan at ", 0), 0u);
}

// Issue 23: the start-up writes every enabled protection's threshold and delay that the device does not
// already hold, inside CONFIG_UPDATE (each a data-memory write followed by its checksum/length and a
// read-back): BQ76952 SCD 100 mV (0x9286 <- 5), SCD Delay 30 us (0x9287 <- 3), SCDL Latch Limit 1, OCC 24 mV,
// OCD1 40 mV and its delay, Enabled Protections C (SCDL, HWDF), HWD Delay 2 s, UTC -5 / UTD -25 / UTINT
// -25 degC, OTD 65 degC, the FET-off pins; BQ76907 COV 4301 mV, CUV 2600 mV, SCD, the host watchdog.
TEST(Bq769x2Bmsctl, AppStartWritesTheProtectionThresholdsAndDelays) {
  const ToolRun o = bmsctl("trace bq76952 app-start");
  ASSERT_EQ(o.status, 0) << printed(o);
  expectInOrder(o, {"S 10 3E 90 00 P", "S 10 3E FA 92 02 P", "S 10 3E FB 92 02 P", "S 10 3E 63 92 42 P",
                    "S 10 3E 5F 92 02 04 P", "S 10 3E 80 92 0C P", "S 10 3E 82 92 14 P", "S 10 3E 83 92 04 P",
                    "S 10 3E 86 92 05 P", "S 10 3E 87 92 03 P", "S 10 3E 95 92 01 P", "S 10 3E 9D 92 41 P",
                    "S 10 3E A6 92 FB P", "S 10 3E A9 92 E7 P", "S 10 3E AC 92 E7 P", "S 10 3E B2 92 02 00 P",
                    "S 10 3E 92 00 P", "# first complete scan at "});
  const ToolRun seven = bmsctl("trace bq76907 app-start");
  ASSERT_EQ(seven.status, 0) << printed(seven);
  expectInOrder(seven,
                {"S 10 3E 90 00 P", "S 10 3E 25 90 01 P", "S 10 3E 32 90 CD 10 P", "S 10 3E 2E 90 28 0A P",
                 "S 10 3E 3C 90 05 P", "S 10 3E 3D 90 03 P", "S 10 3E 2D 90 01 P", "S 10 3E 92 00 P"});
}

// Issue 29: the start-up writes the settings regmapgen generated from the pack file
// (firmware/app/packs/bq76952-evm.yaml, in the pack's order after the board's): the CC gain the 1 mOhm shunt
// gives, 7.5684 mOhm / 1 mOhm (0x91A8 <- F4 0x40F23055), the capacity gain 7.5684 x 298261.6178
// (0x91AC <- F4 0x4A09C74D), the cell inputs (0x9304 <- 0xFFFF), then the pack's protections; on the BQ76907
// the pack's Vcell Mode (0x901B <- 7) and Enabled Protections A (0x9024 <- 0xE1) before its thresholds.
TEST(Bq769x2Bmsctl, AppStartWritesThePackFileSettings) {
  const ToolRun o = bmsctl("trace bq76952 app-start");
  ASSERT_EQ(o.status, 0) << printed(o);
  expectInOrder(
      o, {"S 10 3E 90 00 P", "S 10 3E 04 93 FF FF P", "S 10 3E A8 91 55 30 F2 40 P",
          "S 10 3E AC 91 4D C7 09 4A P", "S 10 3E 61 92 BC P", "S 10 3E 86 92 05 P", "S 10 3E 92 00 P"});
  const ToolRun seven = bmsctl("trace bq76907 app-start");
  ASSERT_EQ(seven.status, 0) << printed(seven);
  expectInOrder(seven, {"S 10 3E 90 00 P", "S 10 3E 1C 90 00 F0 P", "S 10 3E 1B 90 07 P",
                        "S 10 3E 24 90 E1 P", "S 10 3E 32 90 CD 10 P", "S 10 3E 92 00 P"});
}

// On the BQ76907: Balancing Configuration (0x9020) compared, the data-memory write of FET Options 0x901E with
// HOST_FETOFF_EN (bit 6) set, the alarm mask, FET_ENABLE and SLEEP_DISABLE.
TEST(Bq7690xBmsctl, AppStartWritesFetOptionsAndDisablesSleep) {
  const ToolRun o = bmsctl("trace bq76907 app-start");
  ASSERT_EQ(o.status, 0) << printed(o);
  expectInOrder(o, {"S 10 3E 20 90 P", "S 10 3E 90 00 P", "S 10 3E 1E 90 58 P", "S 10 3E 1C 90 00 F0 P",
                    "S 10 3E 92 00 P", "S 10 3E 22 00 P", "S 10 3E 9A 00 P", "S 10 66 00 F0 P",
                    "S 10 62 Sr 11 [", "S 10 3A Sr 11 [", "# first complete scan at "});
  const ToolRun five = bmsctl("trace bq76905 app-start");
  ASSERT_EQ(five.status, 0) << printed(five);
  EXPECT_TRUE(five.has("S 10 3E 1B 90 05 P")) << "Vcell Mode: 5 cells\n" << printed(five);
}

}  // namespace
