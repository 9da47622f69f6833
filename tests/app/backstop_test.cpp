// Each device protection an image enables is configured explicitly, with a legal TRM value, outside the
// firmware limit it backs up (issue 23 item 1): the firmware acts first on every normal limit, the device is
// the backstop. The settings tables (app/monitors/bq769x_settings.hpp) are read back as the device would hold
// them, converted with the TRM's units and the EVM pack's shunt (kShuntMicroOhm), and compared with the
// firmware's limit table (app/protection/default_limits.hpp). Images whose device protections the start-up
// does not write: lp-mspm0g3507-bq79616 (the image enables no OV/UV/OT/UT comparator: its limits are the
// firmware's, acting on the fault output) and lp-mspm0g3507-bq4050 (the gauge's data flash is left as
// shipped; README.md "Open questions").
#include <gtest/gtest.h>

#include <optional>
#include <span>

#include "app/monitors/bq769x_settings.hpp"
#include "app/protection/default_limits.hpp"
#include "regmap/bq7690x_table.hpp"
#include "regmap/bq769x2_table.hpp"

namespace {

namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;
using fw::app::FaultId;
using fw::drivers::bq769x2::Setting;

int32_t limit(FaultId id) {
  return fw::app::kDefaultLimits.rules[static_cast<uint8_t>(id)].trip;
}
int32_t limitDegC(FaultId id) {
  return (limit(id) - fw::app::kDeciKelvinAtZeroCelsius) / 10;
}
// Sense voltage in mV to pack current in mA on the image's shunt.
int32_t milliamps(int32_t mv) {
  return static_cast<int32_t>(static_cast<int64_t>(mv) * 1000000 / fw::packs::bq76952_evm::kShuntMicroOhm);
}

// The value a table writes at `address`, as the device would hold it (sign-extended for a signed entry).
std::optional<int64_t> written(std::span<const Setting> table, std::span<const fw::regmap::EntryInfo> entries,
                               uint16_t address) {
  for (const Setting& s : table) {
    if (s.address != address) continue;
    int64_t v = s.value;
    for (const auto& e : entries)
      if (e.kind == fw::regmap::Kind::DataMemory && e.address == address && e.isSigned)
        v = s.size == 1 ? static_cast<int8_t>(s.value) : s.size == 2 ? static_cast<int16_t>(s.value) : v;
    return v;
  }
  return std::nullopt;
}

// Every value of a table lies within its entry's TRM min..max, and extra ranges the map does not carry.
void expectLegal(std::span<const Setting> table, std::span<const fw::regmap::EntryInfo> entries) {
  for (const Setting& s : table) {
    const fw::regmap::EntryInfo* entry = nullptr;
    for (const auto& e : entries)
      if (e.kind == fw::regmap::Kind::DataMemory && e.address == s.address) entry = &e;
    ASSERT_NE(entry, nullptr) << std::hex << s.address << " is no data-memory entry";
    EXPECT_EQ(entry->size, s.size) << entry->title;
    const int64_t v = *written(table, entries, s.address);
    if (entry->hasMin) {
      EXPECT_GE(v, entry->min) << entry->title;
    }
    if (entry->hasMax) {
      EXPECT_LE(v, entry->max) << entry->title;
    }
  }
}

const std::span<const Setting> kBq76952 = fw::app::kBq76952Settings;
const std::span<const Setting> kBq76907 = fw::app::kBq76907Settings;

int64_t bq76952(uint16_t address) {
  const auto v = written(kBq76952, m2::entries, address);
  EXPECT_TRUE(v) << "0x" << std::hex << address << " is not written";
  return v.value_or(0);
}
int64_t bq76907(uint16_t address) {
  const auto v = written(kBq76907, m7::entries, address);
  EXPECT_TRUE(v) << "0x" << std::hex << address << " is not written";
  return v.value_or(0);
}

// SCD threshold settings in mV (SLUUBY2B Protections:SCD:Threshold; SLUUCJ0 Table 6-9).
constexpr int32_t kScdMv[16] = {10, 20, 40, 60, 80, 100, 125, 150, 175, 200, 250, 300, 350, 400, 450, 500};

TEST(Backstop, EveryValueIsALegalTrmValue) {
  expectLegal(kBq76952, m2::entries);
  expectLegal(kBq76907, m7::entries);
  expectLegal(fw::app::kBq76905Settings, m7::entries);
  // Ranges the register map does not carry: the BQ7690x COV/CUV thresholds 0..5500 mV (SLUUCY8, the same
  // core), its SCD threshold 0..15 (Table 6-9) and delay 0..10 (SLUUCJ0: H1, max 0x0A).
  for (uint16_t a : {m7::dm::CellOvervoltageProtectionThreshold.address,
                     m7::dm::CellUndervoltageProtectionThreshold.address}) {
    EXPECT_GE(bq76907(a), 0);
    EXPECT_LE(bq76907(a), 5500);
  }
  EXPECT_LE(bq76907(m7::dm::ShortCircuitInDischargeProtectionThreshold.address), 15);
  EXPECT_LE(bq76907(m7::dm::ShortCircuitInDischargeProtectionDelay.address), 10);
  EXPECT_LE(bq76952(m2::dm::ScdThreshold.address), 15);
}

// Every protection the BQ76952 table enables has its threshold and its delay in the table (a default left in
// place is how SCD came to trip at 10 mV).
TEST(Backstop, EveryEnabledBq76952ProtectionHasItsThresholdAndDelay) {
  using A = m2::bits::SafetyA;
  using B = m2::bits::SafetyB;
  using C = m2::bits::SafetyC;
  struct Need {
    int64_t enableAddress;
    uint8_t bit;
    uint16_t threshold, delay;
  };
  const uint16_t ea = m2::dm::EnabledProtectionsA.address, eb = m2::dm::EnabledProtectionsB.address,
                 ec = m2::dm::EnabledProtectionsC.address;
  const Need needs[] = {
      {ea, A::cov_mask, m2::dm::CovThreshold.address, m2::dm::CovDelay.address},
      {ea, A::cuv_mask, m2::dm::CuvThreshold.address, m2::dm::CuvDelay.address},
      {ea, A::occ_mask, m2::dm::OccThreshold.address, m2::dm::OccDelay.address},
      {ea, A::ocd1_mask, m2::dm::Ocd1Threshold.address, m2::dm::Ocd1Delay.address},
      {ea, A::ocd2_mask, m2::dm::Ocd2Threshold.address, m2::dm::Ocd2Delay.address},
      {ea, A::scd_mask, m2::dm::ScdThreshold.address, m2::dm::ScdDelay.address},
      {eb, B::otc_mask, m2::dm::OtcThreshold.address, m2::dm::OtcDelay.address},
      {eb, B::otd_mask, m2::dm::OtdThreshold.address, m2::dm::OtdDelay.address},
      {eb, B::otf_mask, m2::dm::OtfThreshold.address, m2::dm::OtfDelay.address},
      {eb, B::otint_mask, m2::dm::OtintThreshold.address, m2::dm::OtintDelay.address},
      {eb, B::utc_mask, m2::dm::UtcThreshold.address, m2::dm::UtcDelay.address},
      {eb, B::utd_mask, m2::dm::UtdThreshold.address, m2::dm::UtdDelay.address},
      {eb, B::utint_mask, m2::dm::UtintThreshold.address, m2::dm::UtintDelay.address},
      {ec, C::ocd3_mask, m2::dm::Ocd3Threshold.address, m2::dm::Ocd3Delay.address},
      {ec, C::scdl_mask, m2::dm::ScdlLatchLimit.address, m2::dm::ScdlRecoveryTime.address},
      {ec, C::hwdf_mask, m2::dm::HwdDelay.address, m2::dm::HwdDelay.address},
  };
  int enabled = 0;
  for (const Need& n : needs) {
    if ((bq76952(static_cast<uint16_t>(n.enableAddress)) & n.bit) == 0) continue;
    ++enabled;
    EXPECT_TRUE(written(kBq76952, m2::entries, n.threshold)) << std::hex << n.threshold;
    if (n.delay != m2::dm::ScdlRecoveryTime.address) {
      EXPECT_TRUE(written(kBq76952, m2::entries, n.delay)) << std::hex << n.delay;
    }
  }
  EXPECT_EQ(enabled, 14) << "SCD OCD1 OCC COV CUV, OTF OTINT OTD OTC UTINT UTD UTC, SCDL HWDF";
}

// The device limit lies beyond the firmware limit it backs up, for each protection of the BQ76952 images.
TEST(Backstop, Bq76952LimitsLieOutsideTheFirmwaresLimits) {
  // Cell voltages: 50.6 mV per step (SLUUBY2B COV/CUV Threshold).
  EXPECT_GT(bq76952(m2::dm::CovThreshold.address) * 506 / 10, limit(FaultId::CellOvervoltage));
  EXPECT_LT(bq76952(m2::dm::CuvThreshold.address) * 506 / 10, limit(FaultId::CellUndervoltage));
  // Currents: 2 mV per step across the shunt (OCC, OCD1), SCD by its setting; SCD beyond OCD1.
  const int32_t occMa = milliamps(static_cast<int32_t>(bq76952(m2::dm::OccThreshold.address) * 2));
  const int32_t ocd1Ma = milliamps(static_cast<int32_t>(bq76952(m2::dm::Ocd1Threshold.address) * 2));
  const int32_t scdMa = milliamps(kScdMv[bq76952(m2::dm::ScdThreshold.address) & 15]);
  EXPECT_GT(occMa, limit(FaultId::ChargeOvercurrent));
  EXPECT_GT(ocd1Ma, -limit(FaultId::DischargeOvercurrent));
  EXPECT_GT(scdMa, ocd1Ma);
  // The firmware's discharge limit is one a 16-bit mA reading can show (CC2 at the default 1 mA userA).
  EXPECT_GT(limit(FaultId::DischargeOvercurrent), INT16_MIN);
  EXPECT_LT(limit(FaultId::ChargeOvercurrent), INT16_MAX);
  // Temperatures in degC: the cell ones beyond the firmware's per-direction limits, the FET and die ones
  // beyond its discharge limits (the firmware's limits look at every sensor).
  EXPECT_GT(bq76952(m2::dm::OtcThreshold.address), limitDegC(FaultId::OvertempCharge));
  EXPECT_GT(bq76952(m2::dm::OtdThreshold.address), limitDegC(FaultId::OvertempDischarge));
  EXPECT_GT(bq76952(m2::dm::OtfThreshold.address), limitDegC(FaultId::OvertempDischarge));
  EXPECT_GT(bq76952(m2::dm::OtintThreshold.address), limitDegC(FaultId::OvertempDischarge));
  EXPECT_LT(bq76952(m2::dm::UtcThreshold.address), limitDegC(FaultId::UndertempCharge));
  EXPECT_LT(bq76952(m2::dm::UtdThreshold.address), limitDegC(FaultId::UndertempDischarge));
  EXPECT_LT(bq76952(m2::dm::UtintThreshold.address), limitDegC(FaultId::UndertempDischarge));
  // The host watchdog outlasts the longest silence of a working firmware (the retry wait after a refused
  // set-up, 1 s), so it acts only when the MCU is gone.
  EXPECT_GT(bq76952(m2::dm::HwdDelay.address) * 1000, 1000);
}

TEST(Backstop, Bq7690xLimitsLieOutsideTheFirmwaresLimits) {
  EXPECT_GT(bq76907(m7::dm::CellOvervoltageProtectionThreshold.address), limit(FaultId::CellOvervoltage));
  EXPECT_LT(bq76907(m7::dm::CellUndervoltageProtectionThreshold.address), limit(FaultId::CellUndervoltage));
  const int32_t scdMa =
      milliamps(kScdMv[bq76907(m7::dm::ShortCircuitInDischargeProtectionThreshold.address)]);
  EXPECT_GT(scdMa, -limit(FaultId::DischargeOvercurrent));
  // Host Watchdog Timeout code 1 = 2 s (SLUUCJ0: codes 0..15 are 1..16 s).
  EXPECT_EQ(bq76907(m7::dm::HostWatchdogTimeout.address) + 1, 2);
  EXPECT_NE(bq76907(m7::dm::EnabledProtectionsB.address) & m7::bits::EnabledProtectionsB::hwd_mask, 0);
}

}  // namespace
