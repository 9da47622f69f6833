// Acceptance 1: every worked example of the seeds, byte for byte on the wire.
//   seed 002 = SLUAA11B (BQ769x2 software development guide), seed 004 = SLUAAM4 (BQ7690x), seed 000 =
//   SLAAEB3 (LP-MSPM0L1306 + BQ76952). The expected bytes below are written out from the seed text, not
//   computed by the code under test.
#include <gtest/gtest.h>

#include <array>

#include "core/crc.hpp"
#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace map7 = fw::regmap::bq7690x;

uint8_t crcOf(std::initializer_list<uint8_t> bytes) {
  const std::vector<uint8_t> v(bytes);
  return fw::crc::crc8(v.data(), v.size());
}

// --- CRC bytes (SLUAA11B / SLUAAM4 section 4) --------------------------------------------------------------

TEST(Bq769x2Seeds, CrcBytesOfTheWorkedExamples) {
  EXPECT_EQ(crcOf({0x10, 0x3E, 0x22}), 0x63);        // FET_ENABLE, first data byte
  EXPECT_EQ(crcOf({0x00}), 0x00);                    // FET_ENABLE, second data byte
  EXPECT_EQ(crcOf({0x10, 0x14, 0x11, 0x68}), 0x33);  // Cell 1 read, first data byte
  EXPECT_EQ(crcOf({0x0B}), 0x31);                    // Cell 1 read, second data byte
  EXPECT_EQ(crcOf({0x10, 0x14, 0x11, 0xC5}), 0x79);  // BQ7690x Cell 1 read, first data byte
}

// --- transfer checksums and lengths ------------------------------------------------------------------------

TEST(Bq769x2Seeds, TransferChecksumsAndLengths) {
  const uint8_t cb[] = {0x02};
  EXPECT_EQ(drv::transferChecksum(0x0083, cb, 1), 0x7A);  // SLUAAM4 2.4: CB_ACTIVE_CELLS 0x02, length 0x05
  const uint8_t ep7[] = {0xE1};
  EXPECT_EQ(drv::transferChecksum(0x9024, ep7, 1), 0x6A);  // SLUAAM4 3.3: 0x9024 <- 0xE1, length 0x05
  const uint8_t ep2[] = {0x8C};
  EXPECT_EQ(drv::transferChecksum(0x9261, ep2, 1),
            static_cast<uint8_t>(~(0x61 + 0x92 + 0x8C)));  // SLUAA11B 3.3
  const uint8_t gain[] = {0x7A, 0x30};
  EXPECT_EQ(drv::transferChecksum(0x9180, gain, 2), 0x44);  // SLUUBY2B 13.1: Cell 1 Gain 12410, length 0x06
}

// --- BQ769x2 (SLUAA11B) ------------------------------------------------------------------------------------

TEST(Bq769x2Seeds, AlarmEnableWriteIsOneDirectWrite) {
  Rig r;
  const uint8_t value[] = {0x82, 0xF0};  // SLUAA11B 1.1: I2C_Write(0x10, 0x66, [0x82, 0xF0])
  ASSERT_EQ(r.runLink(r.driver.link().startWrite(0x66, value)), Status::Ok);
  EXPECT_EQ(r.wire(), (std::vector<std::string>{"S 10 66 82 F0 P"}));
  EXPECT_EQ(r.emu.reg(0x66), 0x82);
  EXPECT_EQ(r.emu.reg(0x67), 0xF0);
}

TEST(Bq769x2Seeds, DirectReadsOfCell1InternalTemperatureAndCurrent) {
  Rig r;  // the emulator starts with SLUAA11B's readings
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x14, 2)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x68, 2)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x3A, 2)), Status::Ok);
  EXPECT_EQ(r.wire(), (std::vector<std::string>{
                          "S 10 14 Sr 11 [74 0E] P",  // 1.2: Cell 1 = 0x0E74 = 3700 mV
                          "S 10 68 Sr 11 [A6 0B] P",  // 1.3: 0x0BA6 = 2982 = 298.2 K
                          "S 10 3A Sr 11 [07 00] P",  // 1.4: 7 mA
                      }));
  const uint8_t* d = r.driver.link().data();
  EXPECT_EQ(d[0] | (d[1] << 8), 7);
}

TEST(Bq769x2Seeds, DeviceNumberThroughTheSubcommandWindow) {
  Rig r;
  r.emu.setDeviceNumber(0x7694);  // SLUAA11B 2.1: "the device number returned is 0x7694 (BQ76942)"
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(id.deviceNumber, 0x7694);
  const auto w = r.wire();
  ASSERT_GE(w.size(), 3u);
  EXPECT_EQ(w[0], "S 10 3E 01 00 P");                 // subcommand 0x0001 little-endian to 0x3E
  EXPECT_TRUE(r.sawLine("S 10 3E Sr 11 [01 00] P"));  // the echo
  // The buffer read: 0x7694 little-endian at 0x40, then 0x60 checksum and 0x61 length (6 = 2 + 4).
  bool found = false;
  for (const auto& l : w)
    if (l.rfind("S 10 40 Sr 11 [94 76 ", 0) == 0 && l.find(" 06] P") != std::string::npos) found = true;
  EXPECT_TRUE(found) << r.wireText();
}

TEST(Bq769x2Seeds, CommandOnlySubcommands) {
  Rig r;
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::FetEnable.address)), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 22 00 P");         // 2.3: 0x0022 to 0x3E
  EXPECT_EQ(r.wire().back(), "S 10 3E Sr 11 [22 00] P");  // the driver waits for the echo
  EXPECT_TRUE(r.emu.fetEnabled());
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::Reset.address, false)), Status::Ok);
  EXPECT_EQ(r.wire().back(), "S 10 3E 12 00 P");  // 2.4: RESET, which never echoes
}

TEST(Bq769x2Seeds, ManufacturingStatusRead) {
  Rig r;
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::sub::ManufacturingStatus.address, 2)),
            Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 57 00 P");  // 2.2: 0x0057 to 0x3E, then two bytes from 0x40
  const auto status = map::bits::ManufacturingStatus::fromRaw(
      static_cast<uint16_t>(r.driver.link().data()[0] | (r.driver.link().data()[1] << 8)));
  EXPECT_FALSE(status.fet_en());  // Mfg Status Init default 0x0040: FET test mode
  EXPECT_TRUE(status.pf_en());
}

TEST(Bq769x2Seeds, ReadEnabledProtectionsADefault) {
  Rig r;
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map::dm::EnabledProtectionsA.address, 1)),
            Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 61 92 P");  // 3.1: RAM address 0x9261
  EXPECT_EQ(r.driver.link().data()[0], 0x88);      // COV + SCD by default
  EXPECT_EQ(r.driver.link().reported(), 32);       // data memory fills the buffer: length 0x24
}

TEST(Bq769x2Seeds, RamWritesInsideConfigUpdate) {
  Rig r;
  const drv::Setting settings[] = {
      drv::setting(map::dm::EnabledProtectionsA, map::bits::SafetyA::fromRaw(0x8C)),  // 3.3
      drv::setting(map::dm::VCellMode, uint16_t{0x037F}),                             // 3.4
  };
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(settings)), fw::s(1)), Status::Ok);
  EXPECT_TRUE(r.sawLine("S 10 3E 90 00 P"));        // 3.2 SET_CFGUPDATE
  EXPECT_TRUE(r.sawLine("S 10 3E 61 92 8C P"));     // 3.3 data after the address
  EXPECT_TRUE(r.sawLine("S 10 60 80 05 P"));        //     checksum ~(0x61+0x92+0x8C), length 5
  EXPECT_TRUE(r.sawLine("S 10 3E 04 93 7F 03 P"));  // 3.4 VCell Mode 0x037F
  EXPECT_TRUE(r.sawLine("S 10 60 E6 06 P"));        //     checksum ~(0x04+0x93+0x7F+0x03), length 6
  EXPECT_TRUE(r.sawLine("S 10 3E 92 00 P"));        // 3.5 EXIT_CFGUPDATE
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x8Cu);
  EXPECT_EQ(r.emu.dataMemory(0x9304, 2), 0x037Fu);
  EXPECT_FALSE(r.emu.inConfigUpdate());
}

TEST(Bq769x2Seeds, CrcModeFetEnableAndCell1) {
  Rig r(crcConfig(true));
  r.emu.setCrc(true);
  r.emu.setCellMv(1, 0x0B68);  // the Cell 1 value of SLUAA11B figure 4-2
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::FetEnable.address)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x14, 2)), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 22 63 00 00 P");         // figure 4-1
  EXPECT_EQ(r.wire().back(), "S 10 14 Sr 11 [68 33 0B 31] P");  // figure 4-2
  const uint8_t* d = r.driver.link().data();
  EXPECT_EQ(d[0] | (d[1] << 8), 0x0B68);
  EXPECT_TRUE(r.emu.fetEnabled());  // the CRC-framed command was accepted
}

// --- BQ7690x (SLUAAM4) -------------------------------------------------------------------------------------

TEST(Bq7690xSeeds, DirectCommands) {
  Rig7690x r(Emu::Model::Bq76905);
  r.emu.setCellMv(1, 3084);               // 1.2: 0x0C0C
  r.emu.setCurrentMa(557);                // 1.4: 0x022D
  const uint8_t enable[] = {0x60, 0x00};  // 1.1: I2C_Write(0x10, 0x66, [0x60, 0x00])
  ASSERT_EQ(r.runLink(r.driver.link().startWrite(0x66, enable)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x14, 2)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x28, 2)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x3A, 2)), Status::Ok);
  EXPECT_EQ(r.wire(), (std::vector<std::string>{
                          "S 10 66 60 00 P",
                          "S 10 14 Sr 11 [0C 0C] P",
                          "S 10 28 Sr 11 [1D 00] P",  // 1.3: 0x001D = 29
                          "S 10 3A Sr 11 [2D 02] P",
                      }));
}

TEST(Bq7690xSeeds, DeviceNumberFetEnableReset) {
  Rig7690x r(Emu::Model::Bq76905);
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(id.deviceNumber, 0x7605);  // 2.1: BQ76905
  r.clearWire();
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map7::sub::FetEnable.address)), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 22 00 P");  // 2.2
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map7::sub::Reset.address, false)), Status::Ok);
  EXPECT_EQ(r.wire().back(), "S 10 3E 12 00 P");  // 2.3
}

TEST(Bq7690xSeeds, CbActiveCellsWriteWithChecksumAndLength) {
  Rig7690x r(Emu::Model::Bq76905);
  ASSERT_EQ(r.run(r.driver.startBalance(0x0001)), Status::Ok);  // cell 1
  const auto w = r.wire();
  ASSERT_GE(w.size(), 2u);
  EXPECT_EQ(w[0], "S 10 3E 83 00 02 P");  // 2.4: 0x0083 and 0x02 to 0x3E
  EXPECT_EQ(w[1], "S 10 60 7A 05 P");     //      checksum 0x7A, length 0x05
  EXPECT_EQ(r.emu.balancing(), 0x0001);
}

TEST(Bq7690xSeeds, RamRegisterReadAndWrites) {
  Rig7690x r(Emu::Model::Bq76905);
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommandRead(map7::dm::EnabledProtectionsA.address, 1)),
            Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 24 90 P");  // 3.1
  EXPECT_EQ(r.driver.link().data()[0], 0xA1);      // COV, SCD and REGOUT by default
  r.clearWire();
  const drv::Setting settings[] = {
      drv::setting(map7::dm::EnabledProtectionsA, map7::bits::EnabledProtectionsA::fromRaw(0xE1)),  // 3.3
      drv::setting(map7::dm::VcellMode, uint8_t{0x04}),                                             // 3.4
  };
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(settings))), Status::Ok);
  EXPECT_TRUE(r.sawLine("S 10 3E 90 00 P"));     // 3.2
  EXPECT_TRUE(r.sawLine("S 10 3E 24 90 E1 P"));  // 3.3
  EXPECT_TRUE(r.sawLine("S 10 60 6A 05 P"));
  EXPECT_TRUE(r.sawLine("S 10 3E 1B 90 04 P"));  // 3.4
  EXPECT_TRUE(r.sawLine("S 10 60 50 05 P"));     //     ~(0x1B+0x90+0x04), length 5
  EXPECT_TRUE(r.sawLine("S 10 3E 92 00 P"));     // 3.5
  EXPECT_EQ(r.emu.dataMemory(0x9024, 1), 0xE1u);
  EXPECT_EQ(r.emu.dataMemory(0x901B, 1), 0x04u);
}

TEST(Bq7690xSeeds, CrcModeFetEnableAndCell1) {
  drv::MonitorConfig config;
  config.link.crc = true;
  Rig7690x r(Emu::Model::Bq76907, config);
  r.emu.setCrc(true);
  r.emu.setCellMv(1, 0x0BC5);  // SLUAAM4 figure 4-2
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map7::sub::FetEnable.address)), Status::Ok);
  ASSERT_EQ(r.runLink(r.driver.link().startRead(0x14, 2)), Status::Ok);
  EXPECT_EQ(r.wire().front(), "S 10 3E 22 63 00 00 P");
  EXPECT_EQ(r.wire().back(), "S 10 14 Sr 11 [C5 79 0B 31] P");
}

// --- BQ76952 on the LP-MSPM0L1306 (SLAAEB3, seed 000) ------------------------------------------------------

// Section 4: with CUV enabled and 1.53 V "cells" (the EVM fed from 24.5 V), Alarm Status reads 0x5082 and
// Safety Status A 0x04 (CUV); the stack reads 0x0988 = 24.4 V in 10 mV units; TS1 0x0B9D = 297.3 K.
TEST(Bq769x2Seeds, Slaaeb3ReadingsDecodeThroughTheTypedRecord) {
  Rig r;
  r.emu.setAllCellsMv(1532);
  r.emu.setStackOverride(0x0988);
  const uint8_t enable[] = {0x82, 0xF0};  // Alarm Enable 0xF082 as SLUAA11B 1.1
  ASSERT_EQ(r.runLink(r.driver.link().startWrite(0x66, enable)), Status::Ok);
  const drv::Setting cuvOn[] = {
      drv::setting(map::dm::EnabledProtectionsA, map::bits::SafetyA::fromRaw(0x8C))};
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(cuvOn))), Status::Ok);
  r.harness.runFor(fw::ms(300));  // CUV Delay default 74 x 3.3 ms
  r.emu.completeScan();
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.alarmStatus.raw(), 0x5082);
  EXPECT_TRUE(m.reg.alarmStatus.ssa() && m.reg.alarmStatus.fullscan() && m.reg.alarmStatus.adscan());
  EXPECT_EQ(m.reg.safetyStatusA.raw(), 0x04);
  EXPECT_TRUE(m.reg.safetyStatusA.cuv());
  EXPECT_EQ(m.reg.cellMv[0], 1532);
  EXPECT_EQ(drv::userVoltsMv(m.reg.stack), 24400);
  EXPECT_EQ(m.reg.ts[0], 2973);
  EXPECT_TRUE(m.deviceFault());
  EXPECT_FALSE(m.reg.fetStatus.dsg_fet());  // CUV opens DSG (DSG FET Protections A default 0xE4)
}

}  // namespace
