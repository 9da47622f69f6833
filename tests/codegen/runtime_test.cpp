// The generated register maps as drivers and tools use them, compiled with the firmware flags (no exceptions,
// no RTTI). Expected values are cited from TI documents (literature number / seed app note) — not read back
// from our own YAML — so a wrong table fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <map>
#include <type_traits>

#include "regmap/bq4050.hpp"
#include "regmap/bq4050_table.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq7690x_table.hpp"
#include "regmap/bq769x2.hpp"
#include "regmap/bq769x2_table.hpp"
#include "regmap/bq79616.hpp"
#include "regmap/bq79616_table.hpp"

namespace {

using namespace fw::regmap;
namespace x2 = fw::regmap::bq769x2;
namespace x0 = fw::regmap::bq7690x;
namespace b16 = fw::regmap::bq79616;
namespace g = fw::regmap::bq4050;

template <class D>
using ValueOf = typename std::remove_cvref_t<D>::value_type;

// --- BQ769x2 ---------------------------------------------------------------------------------------------

TEST(Bq769x2, Cell1VoltageDecodesTheSeedExample) {
  // SLUAA11B table 1-2 (seed 002): 0x14 Cell 1 Voltage, I2, mV, read-only; bytes 74 0E read as 3700 mV.
  static_assert(x2::cmd::Cell1Voltage.address == 0x14);
  static_assert(std::is_same_v<ValueOf<decltype(x2::cmd::Cell1Voltage)>, std::int16_t>);
  static_assert(x2::cmd::Cell1Voltage.unit == Unit::MilliVolt &&
                x2::cmd::Cell1Voltage.order == ByteOrder::Little);
  static_assert(Readable<decltype(x2::cmd::Cell1Voltage)> && !Writable<decltype(x2::cmd::Cell1Voltage)>);
  constexpr std::array<std::uint8_t, 2> wire{0x74, 0x0E};
  static_assert(decode(x2::cmd::Cell1Voltage, wire) == 3700);
  // Seed 000 section 4.6: cell 1 reads 0x05FC = 1532 mV.
  EXPECT_EQ(decode(x2::cmd::Cell1Voltage, std::array<std::uint8_t, 2>{0xFC, 0x05}), 1532);
}

TEST(Bq769x2, TemperaturesAreTenthsOfAKelvin) {
  // SLUAA11B table 1-3 (seed 002): 0x68 reads 0x0BA6 = 2982 -> 298.2 K.
  static_assert(x2::cmd::IntTemperature.address == 0x68);
  static_assert(x2::cmd::IntTemperature.unit == Unit::Kelvin &&
                x2::cmd::IntTemperature.scale == Ratio{1, 10});
  const std::int16_t raw = decode(x2::cmd::IntTemperature, std::array<std::uint8_t, 2>{0xA6, 0x0B});
  EXPECT_EQ(raw, 2982);
  EXPECT_EQ(toUnits(x2::cmd::IntTemperature, raw), 298);       // kelvin, rounded
  EXPECT_EQ(toUnits(x2::cmd::IntTemperature, raw, 10), 2982);  // tenths of a kelvin
  // Seed 000 section 4.5: TS1 reads 0x0B9D = 2973 (297.3 K).
  static_assert(x2::cmd::Ts1Temperature.address == 0x70);
  EXPECT_EQ(decode(x2::cmd::Ts1Temperature, std::array<std::uint8_t, 2>{0x9D, 0x0B}), 2973);
}

TEST(Bq769x2, AlarmEnableWriteMatchesTheSeedBytes) {
  // SLUAA11B table 1-1 (seed 002): 0x66 Alarm Enable, H2, read-write; writing 0xF082 sends [0x82, 0xF0].
  static_assert(x2::cmd::AlarmEnable.address == 0x66 && Writable<decltype(x2::cmd::AlarmEnable)>);
  constexpr auto wire = encode(x2::cmd::AlarmEnable, x2::bits::Alarm::fromRaw(0xF082));
  static_assert(wire[0] == 0x82 && wire[1] == 0xF0);
  // Its reset value comes from Default Alarm Mask, 0xF800 per the same section of SLUAA11B.
  static_assert(x2::dm::DefaultAlarmMask.defaultValue() == 0xF800);
}

TEST(Bq769x2, AlarmStatusIsWriteOneToClearAndDecodesTheSeedReading) {
  static_assert(WriteOneToClear<decltype(x2::cmd::AlarmStatus)>);
  // Seed 000 section 4.1: Alarm Status reads 0x5082 = a Safety Status A flag, full scan done, ADC scan done.
  const x2::bits::AlarmStatus a = decode(x2::cmd::AlarmStatus, std::array<std::uint8_t, 2>{0x82, 0x50});
  EXPECT_TRUE(a.ssa());
  EXPECT_TRUE(a.fullscan());
  EXPECT_TRUE(a.adscan());
  EXPECT_FALSE(a.pf());
  EXPECT_FALSE(a.wake());
}

TEST(Bq769x2, SafetyStatusADecodesUndervoltage) {
  // Seed 000 section 4.2: 0x03 Safety Status A returns 0x04, a cell-undervoltage fault.
  const x2::bits::SafetyStatusA s = decode(x2::cmd::SafetyStatusA, std::array<std::uint8_t, 1>{0x04});
  EXPECT_TRUE(s.cuv());
  EXPECT_FALSE(s.cov());
  EXPECT_FALSE(s.scd());
  static_assert(std::is_same_v<x2::bits::SafetyStatusA, x2::bits::EnabledProtectionsA>);
}

TEST(Bq769x2, EnabledProtectionsADefaultAndTheCuvExample) {
  // SLUAA11B (seed 002): 0x9261 Enabled Protections A, U1, 0x00..0xFF, default 0x88 = COV and SCD enabled;
  // enabling CUV as well writes 0x8C.
  using D = decltype(x2::dm::EnabledProtectionsA);
  static_assert(D::address == 0x9261 && D::size == 1 && ConfigUpdateOnly<D>);
  static_assert(D::hasMin && D::hasMax && D::spec.min == 0x00 && D::spec.max == 0xFF);
  constexpr x2::bits::SafetyA dflt = x2::dm::EnabledProtectionsA.defaultValue();
  static_assert(dflt.raw() == 0x88 && dflt.cov() && dflt.scd() && !dflt.cuv());
  static_assert(encode(x2::dm::EnabledProtectionsA, dflt.with_cuv(true))[0] == 0x8C);
}

TEST(Bq769x2, VCellModeAndOtherSeedEntries) {
  // SLUAA11B (seed 002): 0x9304 VCell Mode, H2, 0x0000..0xFFFF, default 0x0000; 9 cells on a BQ76942 =
  // 0x037F.
  using V = decltype(x2::dm::VCellMode);
  static_assert(V::address == 0x9304 && V::size == 2 && std::is_same_v<V::value_type, std::uint16_t>);
  static_assert(V::spec.max == 0xFFFF && x2::dm::VCellMode.defaultValue() == 0);
  static_assert(encode(x2::dm::VCellMode, 0x037F)[0] == 0x7F);
  // Seed 002 tables: 0x3A CC2 Current I2 userA; 0x0001 DEVICE_NUMBER U2; 0x0057 manufacturing status H2;
  // FET_ENABLE 0x0022, RESET 0x0012, SET_CFGUPDATE 0x0090 and EXIT_CFGUPDATE 0x0092 are command-only.
  static_assert(x2::cmd::Cc2Current.address == 0x3A && x2::cmd::Cc2Current.unit == Unit::UserAmp);
  static_assert(x2::sub::DeviceNumber.address == 0x0001 && x2::sub::DeviceNumber.size == 2);
  static_assert(x2::sub::ManufacturingStatus.address == 0x0057 && x2::sub::ManufacturingStatus.size == 2);
  static_assert(CommandOnly<decltype(x2::sub::FetEnable)> && x2::sub::FetEnable.address == 0x0022);
  static_assert(CommandOnly<decltype(x2::sub::Reset)> && x2::sub::Reset.address == 0x0012);
  static_assert(CommandOnly<decltype(x2::sub::SetCfgupdate)> && x2::sub::SetCfgupdate.address == 0x0090);
  static_assert(CommandOnly<decltype(x2::sub::ExitCfgupdate)> && x2::sub::ExitCfgupdate.address == 0x0092);
  // Seed 000 section 4.6: the stack reads 0x0988 = 2440 userV = 24.4 V with the default 10 mV userV.
  static_assert(x2::cmd::StackVoltage.unit == Unit::UserVolt);
  EXPECT_EQ(decode(x2::cmd::StackVoltage, std::array<std::uint8_t, 2>{0x88, 0x09}), 2440);
}

TEST(Bq769x2, BatteryStatusSecurityEnum) {
  // SLUUCF2C: Battery Status[SEC] = 3 means SEALED.
  const x2::bits::BatteryStatus b = decode(x2::cmd::BatteryStatus, std::array<std::uint8_t, 2>{0x00, 0x03});
  EXPECT_EQ(b.sec(), x2::enums::SecurityState::Sealed);
}

TEST(Bq769x2, FetControlIsNotTheFetStatusLayout) {
  // TI E2E thread 1453973: FET_CONTROL bit 0 is DSG_OFF, FET Status bit 0 is CHG_FET.
  static_assert(x2::bits::FetControl::dsg_off_mask == 0x01 && x2::bits::FetStatus::chg_fet_mask == 0x01);
  static_assert(!std::is_same_v<x2::bits::FetControl, x2::bits::FetStatus>);
  static_assert(Writable<decltype(x2::sub::FetControl)> && !Readable<decltype(x2::sub::FetControl)>);
}

TEST(Bq769x2, SubcommandPayloadTypes) {
  static_assert(std::is_same_v<ValueOf<decltype(x2::sub::CuvSnapshot)>, std::array<std::int16_t, 16>>);
  static_assert(std::is_same_v<ValueOf<decltype(x2::sub::FwVersion)>, std::array<std::uint8_t, 6>>);
  static_assert(x2::sub::ReadCal1.size == 14);  // 12 documented + 2 cell-map bytes (TI E2E)
  constexpr std::array<std::uint8_t, 32> snap{0xFC, 0x05, 0xFD, 0x05};
  const auto cells = decode(x2::sub::CuvSnapshot, snap);
  EXPECT_EQ(cells[0], 1532);
  EXPECT_EQ(cells[1], 1533);
}

TEST(Bq769x2, F4DefaultsAreIeeeBitPatterns) {
  // SLUUBY1B: Calibration:Current:CC Gain default 7.4768.
  static_assert(x2::dm::CcGain.defaultValue().raw() == std::bit_cast<std::uint32_t>(7.4768f));
  EXPECT_FLOAT_EQ(std::bit_cast<float>(x2::dm::CcGain.defaultValue().raw()), 7.4768f);
}

TEST(Bq769x2, RangesAndDefaultsFromSluuby2b) {
  // Issue 26: values SLUUBY2B Table 13-37 gives and the map did not. The firmware's set-up writes REG0 Config
  // 0x01 through setting(), which refuses a value outside the map's range at compile time: that range is now
  // the TRM's 0x00..0x03 (it was 0x00..0xFF).
  static_assert(x2::dm::Reg0Config.spec.hasMax && x2::dm::Reg0Config.spec.max == 0x03);
  static_assert(fw::regmap::inRange(x2::dm::Reg0Config, 0x01) &&
                !fw::regmap::inRange(x2::dm::Reg0Config, 0x04));
  static_assert(x2::dm::HwdDelay.spec.dflt == 60);      // Protections:HWD:Delay, 60 s (was 0)
  static_assert(x2::dm::EnabledPfC.spec.dflt == 0x07);  // was 0x00
  static_assert(x2::dm::CoulombCounterDeadband.spec.scale.num == 234 &&
                x2::dm::CoulombCounterDeadband.spec.unit == fw::regmap::Unit::NanoVolt);  // 234 nV (was 294)
  static_assert(x2::dm::Therm18kCoeffA1.spec.hasDefault && x2::dm::Therm18kCoeffA1.spec.dflt == -15524);
  static_assert(x2::dm::CcGain.spec.unit == fw::regmap::Unit::None);  // a gain, 7.4768 / Rsense
  EXPECT_EQ(x2::dm::HwdDelay.defaultValue(), 60);
}

// --- BQ7690x ---------------------------------------------------------------------------------------------

TEST(Bq7690x, CoreEntries) {
  // SLUAAM4: Cell 1 Voltage 0x14 I2 mV; Enabled Protections A default 0xA1 (COV, SCD, REGOUT); DEVICE_NUMBER
  // 0x0001.
  static_assert(x0::cmd::Cell1Voltage.address == 0x14 && x0::cmd::Cell1Voltage.unit == Unit::MilliVolt);
  constexpr auto prot = x0::dm::EnabledProtectionsA.defaultValue();
  static_assert(prot.raw() == 0xA1 && prot.cov() && prot.scd() && prot.regout() && !prot.cuv());
  static_assert(x0::dm::EnabledProtectionsA.address == 0x9024);
  static_assert(x0::sub::DeviceNumber.address == 0x0001);
  // SLUUCJ0 (BQ76907): Default Alarm Mask 0x901C default 0xC200.
  static_assert(x0::dm::DefaultAlarmMask.address == 0x901C &&
                x0::dm::DefaultAlarmMask.defaultValue() == 0xC200);
  // SLUAAM4's example reads Int Temperature 0x001D as 29 degC: modelled in whole degrees (deviations log).
  static_assert(x0::cmd::IntTemperature.unit == Unit::DegreeCelsius &&
                x0::cmd::IntTemperature.scale == Ratio{1, 1});
  EXPECT_EQ(
      toUnits(x0::cmd::IntTemperature, decode(x0::cmd::IntTemperature, std::array<std::uint8_t, 2>{0x1D, 0})),
      29);
}

// --- BQ79616 ---------------------------------------------------------------------------------------------

TEST(Bq79616, RegistersAreBigEndianBytes) {
  // SLUSE81E register map: CONTROL1 0x0309, VCELL16_HI 0x0568, DEV_REVID 0x0E00.
  static_assert(b16::reg::Control1.address == 0x0309 && b16::reg::Control1.size == 1);
  static_assert(b16::reg::Vcell16Hi.address == 0x0568 && b16::reg::Vcell1Lo.address == 0x0587);
  static_assert(b16::reg::DevRevid.address == 0x0E00);
  static_assert(b16::val::Vcell16.order == ByteOrder::Big && b16::val::Vcell16.size == 2);
  // TI's published wake frame 90 00 03 09 20 13 95 writes 0x20 (SEND_WAKE) to CONTROL1.
  static_assert(encode(b16::reg::Control1, b16::bits::Control1{}.with_send_wake(true))[0] == 0x20);
  // Seed 001: CAN payload "16 C0" is VCELL16 = 0x16C0 big-endian; 5824 x 190.73 uV = 1110812 uV.
  const std::int16_t raw = decode(b16::val::Vcell16, std::array<std::uint8_t, 2>{0x16, 0xC0});
  EXPECT_EQ(raw, 0x16C0);
  EXPECT_EQ(toUnits(b16::val::Vcell16, raw), 1110812);
  // ACTIVE_CELL factory default 0x0A = 16 cells (SLUSE81E).
  static_assert(b16::reg::ActiveCell.defaultValue().num_cell() == b16::enums::ActiveCells::Cells16);
  // 0x310 is reserved in the datasheet summary: read-only here (deviations log).
  static_assert(Readable<decltype(b16::reg::AdcCtrl4)> && !Writable<decltype(b16::reg::AdcCtrl4)>);
}

TEST(Bq79616, CellBalancingRegistersShareOneLayout) {
  static_assert(std::is_same_v<b16::bits::CbCell1Ctrl, b16::bits::CbCellCtrl>);
  static_assert(b16::bits::CbCellCtrl{}.with_time(0x1F).raw() == 0x1F);
  static_assert(b16::bits::CbCellCtrl{}.with_time(0x3F).raw() == 0x1F);  // bits 7:5 are reserved
}

// --- BQ4050 ----------------------------------------------------------------------------------------------

TEST(Bq4050, SbsAndMacEntries) {
  // SBS 1.1: Voltage 0x09 mV, Temperature 0x08 in 0.1 K, RelativeStateOfCharge 0..100 %.
  static_assert(g::sbs::Voltage.address == 0x09 && g::sbs::Voltage.unit == Unit::MilliVolt &&
                g::sbs::Voltage.size == 2);
  static_assert(g::sbs::Temperature.unit == Unit::Kelvin && g::sbs::Temperature.scale == Ratio{1, 10});
  static_assert(inRange(g::sbs::RelativeStateOfCharge, 100) && !inRange(g::sbs::RelativeStateOfCharge, 101));
  // SLUUAQ3A: ManufacturerBlockAccess 0x44 is read-write; MAC DeviceType 0x0001 returns 0x4050.
  static_assert(g::sbs::ManufacturerBlockAccess.address == 0x44 &&
                Writable<decltype(g::sbs::ManufacturerBlockAccess)>);
  static_assert(g::mac::DeviceType.address == 0x0001 && g::mac::DeviceType.size == 2);
  static_assert(CommandOnly<decltype(g::mac::DeviceReset)> && g::mac::DeviceReset.address == 0x0041);
  // SBS 1.1 BatteryStatus: EC in bits 3:0; INIT is bit 7.
  const g::bits::BatteryStatus st = decode(g::sbs::BatteryStatus, std::array<std::uint8_t, 2>{0x84, 0x00});
  EXPECT_TRUE(st.init());
  EXPECT_EQ(st.ec(), g::enums::SbsErrorCode::AccessDenied);
  // OperationStatus is a 4-byte block holding one 32-bit flag word.
  const g::bits::OperationStatus op =
      decode(g::sbs::OperationStatus, std::array<std::uint8_t, 4>{0x06, 0x03, 0, 0});
  EXPECT_TRUE(op.chg());
  EXPECT_TRUE(op.dsg());
  EXPECT_EQ(op.sec(), g::enums::SecurityMode::Sealed);
  // Variable-length blocks keep their length.
  const auto name = decode(g::sbs::ManufacturerName, std::array<std::uint8_t, 2>{'T', 'I'});
  EXPECT_EQ(name.length, 2);
  EXPECT_EQ(name.data[1], 'I');
}

// --- runtime tables --------------------------------------------------------------------------------------

TEST(Tables, LookupByNameIgnoresCaseAndUnderscores) {
  const EntryInfo* e = findByName(x2::entries, "cell_1_voltage");
  ASSERT_NE(e, nullptr);
  EXPECT_STREQ(e->name, "Cell1Voltage");
  EXPECT_STREQ(e->title, "Cell 1 Voltage");
  EXPECT_STREQ(e->type, "I2");
  EXPECT_STREQ(unitSymbol(e->unit), "mV");
  EXPECT_EQ(findByName(x2::entries, "FET_ENABLE"), findByName(x2::entries, "FetEnable"));
  EXPECT_EQ(findByName(x2::entries, "FET_ENABLE")->address, 0x0022u);
  EXPECT_EQ(findByName(x2::entries, "no such entry"), nullptr);
  // Kinds that share a name are told apart by their namespace.
  const EntryInfo* sbs = findByName(g::entries, "sbs::SafetyStatus");
  const EntryInfo* mac = findByName(g::entries, "mac.SafetyStatus");
  ASSERT_TRUE(sbs && mac);
  EXPECT_EQ(sbs->kind, Kind::Sbs);
  EXPECT_EQ(mac->kind, Kind::Mac);
  EXPECT_EQ(findByName(g::entries, "SafetyStatus"), sbs);  // unqualified: first in table order
}

TEST(Tables, LookupByAddressAndCodeRanges) {
  const EntryInfo* e = findByAddress(x2::entries, Kind::DataMemory, 0x9261);
  ASSERT_NE(e, nullptr);
  EXPECT_STREQ(e->name, "EnabledProtectionsA");
  EXPECT_TRUE(e->hasDefault);
  EXPECT_EQ(e->dflt, 0x88);
  ASSERT_EQ(e->fields.size(), 6u);
  EXPECT_STREQ(e->fields[0].name, "cuv");  // LSB first
  EXPECT_EQ(e->fields[0].lsb, 2);
  // MAC 0x4000..0x5FFF reach data flash: any address in the range finds the window.
  const EntryInfo* df = findByAddress(g::entries, Kind::Mac, 0x4481);
  ASSERT_NE(df, nullptr);
  EXPECT_STREQ(df->name, "DataFlashAccess");
  EXPECT_EQ(findByAddress(x2::entries, Kind::Command, 0x15), nullptr);  // inside Cell 1 Voltage, not a start
}

TEST(Tables, DecodeRawFormatsAToolLine) {
  const EntryInfo& e = *findByName(x2::entries, "Cell1Voltage");
  const std::array<std::uint8_t, 2> wire{0x74, 0x0E};
  EXPECT_EQ(decodeRaw(e, wire), 3700);  // bmsctl: "# Cell1Voltage = 3700 mV"
  const EntryInfo& ocd3 = *findByName(x2::entries, "dm::Ocd3Threshold");
  std::array<std::uint8_t, 2> out{};
  ASSERT_EQ(encodeRaw(ocd3, -4000, out), 2u);
  EXPECT_EQ(decodeRaw(ocd3, out), -4000);  // sign-extended
  const EntryInfo& v = *findByName(b16::entries, "val::Vcell16");
  EXPECT_EQ(decodeRaw(v, std::array<std::uint8_t, 2>{0xFF, 0xFE}), -2);        // big-endian, signed
  EXPECT_EQ(decodeRaw(*findByName(x2::entries, "sub::CuvSnapshot"), out), 0);  // arrays are not scalars
}

TEST(Tables, EmulatorCanInitialiseDataMemoryFromDefaults) {
  // What a BQ769x2 emulator does: fill data memory with every TRM default.
  std::map<std::uint32_t, std::uint8_t> memory;
  int withDefault = 0;
  for (const EntryInfo& e : x2::entries) {
    if (e.kind != Kind::DataMemory || !e.hasDefault) continue;
    std::array<std::uint8_t, 8> bytes{};
    const std::size_t n = encodeRaw(e, e.dflt, bytes);
    ASSERT_EQ(n, e.size) << e.name;
    for (std::size_t i = 0; i < n; ++i)
      memory[e.address + static_cast<std::uint32_t>(i)] = bytes[i];
    ++withDefault;
  }
  EXPECT_GE(withDefault, 270);  // 272 parameters; SLUUBY2B Table 13-37 gives a default for nearly all
  EXPECT_EQ(memory.at(0x9261), 0x88);
  EXPECT_EQ(memory.at(0x926D), 0x00);  // Default Alarm Mask 0xF800, little-endian
  EXPECT_EQ(memory.at(0x926E), 0xF8);
}

TEST(Tables, EveryFamilyTableMatchesItsKindCounts) {
  auto count = [](std::span<const EntryInfo> t, Kind k) {
    return std::count_if(t.begin(), t.end(), [k](const EntryInfo& e) { return e.kind == k; });
  };
  EXPECT_GE(count(x2::entries, Kind::Command), 55);
  EXPECT_GE(count(x2::entries, Kind::Subcommand), 77);  // SLUUBY2B Tables 12-22 and 12-23
  EXPECT_GE(count(x2::entries, Kind::DataMemory), 270);
  EXPECT_GE(count(x0::entries, Kind::Command), 30);
  EXPECT_GE(count(x0::entries, Kind::Subcommand), 19);
  EXPECT_GE(count(x0::entries, Kind::DataMemory), 70);
  EXPECT_GE(count(b16::entries, Kind::Register), 300);
  EXPECT_GE(count(g::entries, Kind::Sbs), 55);
  EXPECT_GE(count(g::entries, Kind::Mac), 50);
  EXPECT_EQ(count(g::entries, Kind::DataFlash), 538);  // SLUUAQ3A Table 14-1
}

}  // namespace
