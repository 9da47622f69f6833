// `bmsctl trace bq4050` as a user runs it: the built binary, its stdout, stderr and exit status
// (README "Host tools"). PECs are checked with the test's own bitwise CRC-8.
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rig.hpp"
#include "support/tool_run.hpp"

#ifndef BMSCTL_PATH
#error "BMSCTL_PATH must name the bmsctl binary"
#endif

namespace bq4050_test {
namespace {

using test::ToolRun;

ToolRun bmsctl(const std::string& args) {
  return test::runTool(std::string(BMSCTL_PATH) + " trace bq4050 " + args);
}

uint8_t hexByte(const std::string& s) {
  return static_cast<uint8_t>(std::stoul(s, nullptr, 16));
}

TEST(Bq4050Bmsctl, PecWordReadOfVoltageCarriesACorrectPec) {
  // Acceptance 1: `bmsctl trace bq4050 --pec word 0x09` prints S 16 09 Sr 17 [lo hi pec] P.
  const ToolRun r = bmsctl("--pec word 0x09");
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_GE(r.out.size(), 2u);
  std::smatch m;
  const std::regex line(R"(S 16 09 Sr 17 \[([0-9A-F]{2}) ([0-9A-F]{2}) ([0-9A-F]{2})\] P)");
  ASSERT_TRUE(std::regex_match(r.out[0], m, line)) << r.out[0];
  const uint8_t lo = hexByte(m[1]), hi = hexByte(m[2]), pec = hexByte(m[3]);
  EXPECT_EQ(pec, referenceCrc8({0x16, 0x09, 0x17, lo, hi}));
  EXPECT_EQ(r.out[1], "# Voltage = " + std::to_string(lo | (hi << 8)) + " mV");
  EXPECT_TRUE(r.err.empty());
}

TEST(Bq4050Bmsctl, NamesAndHexAddressesAreTheSame) {
  const ToolRun byName = bmsctl("--pec word Voltage");
  const ToolRun byHex = bmsctl("--pec word 09");
  ASSERT_EQ(byName.status, 0);
  EXPECT_EQ(byName.out, byHex.out);
}

TEST(Bq4050Bmsctl, WithoutPecEveryValueIsReadTwice) {
  const ToolRun r = bmsctl("word Temperature");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out[0], "S 16 08 Sr 17 [A6 0B] P");
  EXPECT_EQ(r.out[1], "S 16 08 Sr 17 [A6 0B] P");
  EXPECT_EQ(r.out[2], "# Temperature = 298.2 K (raw 2982)");
}

TEST(Bq4050Bmsctl, MacDeviceTypeTrace) {
  const ToolRun r = bmsctl("--pec mac DeviceType");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out[0], "S 16 44 02 01 00 " + hex({referenceCrc8({0x16, 0x44, 0x02, 0x01, 0x00})}) + " P");
  EXPECT_EQ(r.out[1], "S 16 44 Sr 17 [04 01 00 50 40 " +
                          hex({referenceCrc8({0x16, 0x44, 0x17, 0x04, 0x01, 0x00, 0x50, 0x40})}) + "] P");
  EXPECT_TRUE(r.has("# DeviceType = 0x4050"));
  EXPECT_EQ(bmsctl("--pec mac 0x0001").out, r.out);
}

TEST(Bq4050Bmsctl, BlockAndCommandOnlyMac) {
  const ToolRun block = bmsctl("block ManufacturerName");
  ASSERT_EQ(block.status, 0) << block.err;
  EXPECT_TRUE(block.has("# ManufacturerName = \"Texas Inst.\""));
  const ToolRun cmd = bmsctl("mac FETControl");
  ASSERT_EQ(cmd.status, 0) << cmd.err;
  EXPECT_EQ(cmd.out[0], "S 16 00 22 00 P");
  EXPECT_TRUE(cmd.has("# FETControl (0x0022) sent through ManufacturerAccess"));
}

TEST(Bq4050Bmsctl, BadArgumentsAreUsageErrorsWithStatus2) {
  for (const char* args :
       {"", "read 0x09", "word", "word 0x09 0x0A", "word NoSuchThing", "word 0x100", "mac 0x10000",
        "word ManufacturerName", "--crc word 0x09", "--pec=1 word 0x09", "word mac::SafetyStatus"}) {
    SCOPED_TRACE(args);
    const ToolRun r = bmsctl(args);
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(r.out.empty()) << "nothing on stdout for a usage error";
    EXPECT_EQ(r.err.rfind("bmsctl: error: ", 0), 0u) << r.err;
  }
}

TEST(Bq4050Bmsctl, FailedOperationPrintsTheTraceAndTheErrorWithStatus1) {
  const ToolRun r = bmsctl("--pec word 0x45");  // no such SBS command: the gauge refuses the command byte
  EXPECT_EQ(r.status, 1);
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out[0], "S 16 45 NACK P");
  EXPECT_EQ(r.out.back(), "# error: DataNack");
}

// Issue 12: `app-start` is the application's own start-up: the probe (SpecificationInfo read until two reads
// agree, then PEC on; DeviceType, FirmwareVersion through ManufacturerBlockAccess), then the first scan.
TEST(Bq4050Bmsctl, AppStartTracesTheApplicationFromResetToItsFirstScan) {
  const ToolRun r = bmsctl("app-start");
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_GE(r.out.size(), 8u);
  EXPECT_EQ(r.out[0], "S 16 1A Sr 17 [31 00] P");  // SpecificationInfo without PEC...
  EXPECT_EQ(r.out[1], "S 16 1A Sr 17 [31 00] P");  // ...twice: the two reads must agree
  EXPECT_EQ(r.out[2], "S 16 44 02 01 00 " + hex({referenceCrc8({0x16, 0x44, 0x02, 0x01, 0x00})}) + " P");
  EXPECT_TRUE(r.has("S 16 44 02 54 00 " + hex({referenceCrc8({0x16, 0x44, 0x02, 0x54, 0x00})}) + " P"))
      << "the scan ends with OperationStatus";
  EXPECT_EQ(r.out.back().rfind("# app-start: first complete scan at ", 0), 0u) << r.out.back();
  EXPECT_NE(r.out.back().find("(valid), pec=on"), std::string::npos) << r.out.back();
  EXPECT_EQ(bmsctl("--pec app-start").status, 2);
}

}  // namespace
}  // namespace bq4050_test
