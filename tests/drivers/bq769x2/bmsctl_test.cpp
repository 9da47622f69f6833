// Runs the built bmsctl binary and checks its output against the contract (ARCHITECTURE.md "Host tools") and
// the seeds' wire bytes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

namespace {

struct Output {
  int status = -1;
  std::string out;
};

Output bmsctl(const std::string& args) {
  Output o;
  const std::string cmd = std::string(BMSCTL_PATH) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return o;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), buf.size(), p) != nullptr)
    o.out += buf.data();
  const int raw = pclose(p);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

bool hasLine(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

TEST(Bq769x2Bmsctl, CrcFetEnableIsTheContractLine) {
  const Output o = bmsctl("trace bq76952 --crc subcmd 0x0022");
  EXPECT_EQ(o.status, 0) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 22 63 00 00 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# FetEnable (0x0022) sent")) << o.out;
}

TEST(Bq769x2Bmsctl, ReadByNameDecodesWithUnit) {
  const Output o = bmsctl("trace bq76952 read Cell1Voltage 2");
  EXPECT_EQ(o.status, 0);
  EXPECT_EQ(o.out, "S 10 14 Sr 11 [74 0E] P\n# Cell1Voltage = 3700 mV\n");
  const Output t = bmsctl("trace bq76952 read IntTemperature 2");
  EXPECT_TRUE(hasLine(t.out, "# IntTemperature = 298.2 K")) << t.out;
}

TEST(Bq769x2Bmsctl, BlockReadDecodesEveryCommandInIt) {
  const Output o = bmsctl("trace bq76952 read 0x14 40");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(hasLine(o.out, "# Cell16Voltage = 3700 mV")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# StackVoltage = 5920 userV")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# Cc2Current = 7 userA")) << o.out;
}

TEST(Bq769x2Bmsctl, WriteSubcommandsAndDataMemory) {
  Output o = bmsctl("trace bq76952 write 0x66 82 F0");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(hasLine(o.out, "S 10 66 82 F0 P")) << o.out;
  o = bmsctl("trace bq76952 subcmd FET_ENABLE");
  EXPECT_EQ(o.out.substr(0, 16), "S 10 3E 22 00 P\n") << o.out;     // SLUAA11B 2.3
  EXPECT_TRUE(hasLine(o.out, "S 10 3E Sr 11 [22 00] P")) << o.out;  // the echo: it has run
  EXPECT_TRUE(hasLine(o.out, "# FetEnable (0x0022) sent")) << o.out;
  o = bmsctl("trace bq76952 subcmd RESET");
  EXPECT_EQ(o.out, "S 10 3E 12 00 P\n# Reset (0x0012) sent\n");  // SLUAA11B 2.4: no echo after a reset
  o = bmsctl("trace bq76952 subcmd-read 0x0001");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 01 00 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# DeviceNumber = 0x7695 (30357)")) << o.out;
  o = bmsctl("trace bq76952 dm-read 0x9261 1");
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 61 92 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# EnabledProtectionsA = 0x88 (COV SCD)")) << o.out;
  o = bmsctl("trace bq76952 dm-write 0x9261 8C");
  EXPECT_EQ(o.status, 0) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 90 00 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 61 92 8C P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 60 80 05 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 92 00 P")) << o.out;
  o = bmsctl("trace bq76952 dm-write EnabledProtectionsA 88");  // already the value: no CONFIG_UPDATE
  EXPECT_EQ(o.out.find("3E 90 00"), std::string::npos) << o.out;
}

TEST(Bq769x2Bmsctl, Bq7690xDevices) {
  Output o = bmsctl("trace bq76907 --crc read 0x14 2");
  EXPECT_EQ(o.status, 0);
  EXPECT_TRUE(hasLine(o.out, "# Cell1Voltage = 3089 mV")) << o.out;
  o = bmsctl("trace bq76905 subcmd-read DEVICE_NUMBER");
  EXPECT_TRUE(hasLine(o.out, "# DeviceNumber = 0x7605 (30213)")) << o.out;
  o = bmsctl("trace bq76905 dm-write 0x9024 E1");
  EXPECT_TRUE(hasLine(o.out, "S 10 3E 24 90 E1 P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "S 10 60 6A 05 P")) << o.out;
}

TEST(Bq769x2Bmsctl, FailedOperationPrintsTheTraceAndTheStatus) {
  Output o = bmsctl("trace bq76952 --address=0x10 read 0x14 2");
  EXPECT_EQ(o.status, 1);
  EXPECT_TRUE(hasLine(o.out, "S 20 NACK P")) << o.out;
  EXPECT_TRUE(hasLine(o.out, "# error: Nack")) << o.out;
  o = bmsctl("trace bq76952 --fault=nack-always subcmd-read 0x0001");
  EXPECT_EQ(o.status, 1);
  EXPECT_TRUE(hasLine(o.out, "# error: Nack")) << o.out;
  o = bmsctl("trace bq76952 --fault=checksum subcmd-read 0x0001");  // one fault: the retry succeeds
  EXPECT_EQ(o.status, 0) << o.out;
}

TEST(Bq769x2Bmsctl, BadArgumentsExitTwoWithoutTouchingTheBus) {
  for (const char* args :
       {"trace bq76952 read Nope 2", "trace bq76952 read 0x14", "trace bq76952 read 0x14 99",
        "trace bq76952 frobnicate 0x14", "trace bq76952 --pec read 0x14 2", "trace bq76952 write 0x66 XYZ",
        "trace bq76952 dm-read Cell1Voltage 2", "trace bq76952 --fault=gremlins subcmd 0x22"}) {
    const Output o = bmsctl(args);
    EXPECT_EQ(o.status, 2) << args << "\n" << o.out;
    EXPECT_NE(o.out.find("bmsctl: error:"), std::string::npos) << args;
    EXPECT_EQ(o.out.find("S 10"), std::string::npos) << args;
  }
}

}  // namespace
