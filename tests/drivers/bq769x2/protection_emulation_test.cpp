// The emulator's own protections, as TI documents them, driven through the backend (current, cells) and raw
// bus transactions: the comparator protections (SCD, OCC, OCD1) at their thresholds and delays and their
// recovery, the SCD latch, the host watchdog and the CFETOFF / DFETOFF pins. The BQ76952's data memory starts
// at its defaults (SLUUBY2B): SCD Threshold 10 mV, which a 10 A load on the EVM's 1 mOhm shunt reaches.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace map7 = fw::regmap::bq7690x;

// A BQ76952 out of FET test mode, both FETs on, SLEEP disabled (as the images run it: in SLEEP the CHG FET
// is off, SLUUBY2B 7.3).
struct Device : Raw {
  Device() {
    EXPECT_EQ(write({0x3E, 0x22, 0x00}), Status::Ok);  // FET_ENABLE
    h.runFor(fw::ms(1));
    EXPECT_EQ(write({0x3E, 0x9A, 0x00}), Status::Ok);  // SLEEP_DISABLE
    h.runFor(fw::ms(1));
    EXPECT_TRUE(emu.chgFet() && emu.dsgFet());
  }
  void set1(uint16_t address, uint32_t value) { emu.setDataMemory(address, value, 1); }
  void set2(uint16_t address, uint32_t value) { emu.setDataMemory(address, value, 2); }
};

// Issue 23: SCD at its 10 mV default, the configuration the images wrote before: a 10 A load on the 1 mOhm
// shunt is a "short circuit" and opens DSG after the default delay ((2 - 1) x 15 us).
TEST(Bq769x2Protections, TheDefaultScdThresholdTripsAtTenAmperes) {
  Device d;
  ASSERT_EQ(d.emu.dataMemory(map::dm::ScdThreshold.address, 1), 0u) << "SLUUBY2B default: 10 mV";
  // What the images wrote: TI's protections, OCC 20 mV, OCD1 100 mV, SCD left alone.
  d.set1(map::dm::EnabledProtectionsA.address, 0xBC);
  d.set1(map::dm::OccThreshold.address, 10);
  d.set1(map::dm::Ocd1Threshold.address, 50);
  d.emu.setCurrentMa(-9900);
  d.h.runFor(fw::ms(5));
  EXPECT_TRUE(d.emu.dsgFet()) << "9.9 mV: under the threshold";
  d.emu.setCurrentMa(-10000);
  EXPECT_TRUE(d.emu.safetyAlertA() & map::bits::SafetyA::scd_mask) << "the alert at once";
  d.h.runFor(fw::us(14));
  EXPECT_TRUE(d.emu.dsgFet()) << "the delay (15 us) has not passed";
  d.h.runFor(fw::us(2));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask);
  EXPECT_FALSE(d.emu.dsgFet()) << "a 10 A load opens DSG";
  // It recovers on a timer (SCD Recovery Time, default 5 s): with the load still there it trips again.
  d.h.runFor(fw::s(5) + fw::ms(1));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask) << "tripped again at once";
  d.emu.setCurrentMa(0);
  d.h.runFor(fw::s(5));
  EXPECT_FALSE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask);
  EXPECT_TRUE(d.emu.dsgFet());
}

// SCD at the images' 100 mV and (3 - 1) x 15 us = 30 us: 40 A does nothing, 120 A trips after 30 us.
TEST(Bq769x2Protections, ScdTripsAtItsThresholdAfterItsDelay) {
  Device d;
  d.set1(map::dm::ScdThreshold.address, 5);  // 100 mV
  d.set1(map::dm::ScdDelay.address, 3);
  d.emu.setCurrentMa(-40000);  // 40 mV: under 100 mV
  d.h.runFor(fw::ms(1));
  EXPECT_FALSE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask);
  d.emu.setCurrentMa(0);
  d.h.runFor(fw::s(4));
  d.emu.setCurrentMa(-120000);
  d.h.runFor(fw::us(29));
  EXPECT_FALSE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask);
  d.h.runFor(fw::us(2));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask);
  EXPECT_FALSE(d.emu.dsgFet());
}

// OCC (SLUUBY2B 5.2): 2 mV x threshold for 3.3 ms x (2 + delay) opens CHG; it recovers only with a discharge
// current <= OCC Recovery Threshold (-200 mA) for Recovery:Time (3 s), not with the charger merely blocked.
TEST(Bq769x2Protections, OccTripsAfterItsDelayAndRecoversOnADischarge) {
  Device d;
  d.set1(map::dm::EnabledProtectionsA.address, 0xBC);  // SCD, OCD1, OCC, COV, CUV
  d.set1(map::dm::OccThreshold.address, 12);           // 24 mV: 24 A
  d.set1(map::dm::OccDelay.address, 4);                // 19.8 ms
  d.emu.setCurrentMa(23000);
  d.h.runFor(fw::ms(50));
  EXPECT_TRUE(d.emu.chgFet()) << "23 A: under 24 A";
  d.emu.setCurrentMa(25000);
  d.h.runFor(fw::us(19700));
  EXPECT_TRUE(d.emu.chgFet());
  d.h.runFor(fw::us(200));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::occ_mask);
  EXPECT_FALSE(d.emu.chgFet());
  EXPECT_TRUE(d.emu.dsgFet()) << "OCC opens CHG only (CHG FET Protections A)";
  d.emu.setCurrentMa(0);  // the charge path is open: nothing flows
  d.h.runFor(fw::s(10));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::occ_mask) << "no relieving current, no recovery";
  d.emu.setCurrentMa(-500);
  d.h.runFor(fw::ms(2990));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::occ_mask);
  d.h.runFor(fw::ms(20));
  EXPECT_FALSE(d.emu.safetyStatusA() & map::bits::SafetyA::occ_mask);
  EXPECT_TRUE(d.emu.chgFet());
}

// OCD1: the discharge side, DSG; recovers with a charge current >= OCD Recovery Threshold (200 mA).
TEST(Bq769x2Protections, Ocd1OpensDischargeAndRecoversOnACharge) {
  Device d;
  d.set1(map::dm::EnabledProtectionsA.address, 0xBC);
  d.set1(map::dm::Ocd1Threshold.address, 20);  // 40 mV: 40 A
  d.set1(map::dm::Ocd1Delay.address, 4);
  d.set1(map::dm::ScdThreshold.address, 5);  // keep SCD (10 mV default) out of it
  d.emu.setCurrentMa(-45000);
  d.h.runFor(fw::ms(20));
  EXPECT_TRUE(d.emu.safetyStatusA() & map::bits::SafetyA::ocd1_mask);
  EXPECT_FALSE(d.emu.dsgFet());
  EXPECT_TRUE(d.emu.chgFet());
  d.emu.setCurrentMa(0);
  d.h.runFor(fw::s(5));
  EXPECT_FALSE(d.emu.dsgFet()) << "a removed load alone does not recover it";
  d.emu.setCurrentMa(1000);
  d.h.runFor(fw::ms(3010));
  EXPECT_TRUE(d.emu.dsgFet());
}

// The SCD latch (SLUUCG7 Protection Configuration[SCDL_CURR_RECOV]): with Latch Limit 1 and the latch enabled
// the first SCD latches DSG off past SCD Recovery Time; a charge current of 200 mA for SCDL Recovery Time
// (15 s) recovers it.
TEST(Bq769x2Protections, TheScdLatchHoldsUntilAChargeCurrent) {
  Device d;
  d.set1(map::dm::ScdThreshold.address, 5);
  d.set1(map::dm::ScdlLatchLimit.address, 1);
  d.set1(map::dm::EnabledProtectionsC.address, map::bits::SafetyC::scdl_mask);
  d.set2(map::dm::ProtectionConfiguration.address, 0x0402);
  d.emu.setCurrentMa(-150000);
  d.h.runFor(fw::ms(1));
  EXPECT_TRUE(d.emu.safetyStatusC() & map::bits::SafetyC::scdl_mask);
  d.emu.setCurrentMa(0);
  d.h.runFor(fw::s(10));
  EXPECT_FALSE(d.emu.safetyStatusA() & map::bits::SafetyA::scd_mask) << "SCD recovered on its timer";
  EXPECT_FALSE(d.emu.dsgFet()) << "the latch holds DSG off (DSG FET Protections C[SCDL])";
  d.emu.setCurrentMa(500);
  d.h.runFor(fw::s(15) + fw::ms(10));
  EXPECT_FALSE(d.emu.safetyStatusC() & map::bits::SafetyC::scdl_mask);
  EXPECT_TRUE(d.emu.dsgFet());
}

// The host watchdog (SLUUBY2B 5.2): with Enabled Protections C[HWDF] and HWD Delay 2 s, no transaction for
// 2 s opens both FETs (CHG/DSG FET Protections C[HWDF] defaults); the next transaction recovers it.
TEST(Bq769x2Protections, TheHostWatchdogOpensBothFetsWhenTheHostIsSilent) {
  Device d;
  d.set1(map::dm::EnabledProtectionsC.address, map::bits::SafetyC::hwdf_mask);
  d.set2(map::dm::HwdDelay.address, 2);
  for (int i = 0; i < 30; ++i) {  // a host that talks every 100 ms
    d.h.runFor(fw::ms(100));
    d.read(0x12, 2);
  }
  EXPECT_TRUE(d.emu.chgFet() && d.emu.dsgFet());
  d.h.runFor(fw::ms(1990));
  EXPECT_TRUE(d.emu.chgFet() && d.emu.dsgFet());
  d.h.runFor(fw::ms(20));
  EXPECT_TRUE(d.emu.safetyStatusC() & map::bits::SafetyC::hwdf_mask);
  EXPECT_FALSE(d.emu.chgFet() || d.emu.dsgFet());
  d.read(0x12, 2);
  EXPECT_FALSE(d.emu.safetyStatusC() & map::bits::SafetyC::hwdf_mask);
  EXPECT_TRUE(d.emu.chgFet() && d.emu.dsgFet());
}

// CFETOFF / DFETOFF (SLUAAQ5): configured as their FET-off function, active-high (0x02), each opens its FET
// while driven high; unconfigured (0x00, the default) they do nothing.
TEST(Bq769x2Protections, FetOffPinsOpenTheirFetWhenConfigured) {
  Device d;
  d.emu.setFetOffPins(true, true);
  EXPECT_TRUE(d.emu.chgFet() && d.emu.dsgFet()) << "pins not configured";
  d.set1(map::dm::CfetoffPinConfig.address, 0x02);
  d.set1(map::dm::DfetoffPinConfig.address, 0x02);
  d.emu.setFetOffPins(true, false);
  EXPECT_FALSE(d.emu.chgFet());
  EXPECT_TRUE(d.emu.dsgFet());
  d.emu.setFetOffPins(false, true);
  EXPECT_TRUE(d.emu.chgFet());
  EXPECT_FALSE(d.emu.dsgFet());
  d.set1(map::dm::DfetoffPinConfig.address, 0x42);  // BOTHOFF
  EXPECT_FALSE(d.emu.chgFet() || d.emu.dsgFet());
  d.emu.setFetOffPins(false, false);
  EXPECT_TRUE(d.emu.chgFet() && d.emu.dsgFet());
}

// BQ7690x: SCD (SLUUCJ0 6.5, Table 6-9 / 6-10) opens DSG; the host watchdog (SLUUCJ0 6.15) alerts at half its
// timeout, trips at the whole and opens DSG (DSG FET Protections A[HWD]).
TEST(Bq7690xProtections, ScdAndTheHostWatchdogOpenDischarge) {
  Raw r(Emu::Model::Bq76907);
  ASSERT_EQ(r.write({0x3E, 0x22, 0x00}), Status::Ok);  // FET_ENABLE: autonomous FET control
  r.h.runFor(fw::ms(3));
  r.emu.setDataMemory(map7::dm::ShortCircuitInDischargeProtectionThreshold.address, 5, 1);  // 100 mV
  r.emu.setDataMemory(map7::dm::ShortCircuitInDischargeProtectionDelay.address, 3, 1);      // 61 us
  ASSERT_TRUE(r.emu.dsgFet());
  r.emu.setCurrentMa(-120000);
  r.h.runFor(fw::us(60));
  EXPECT_TRUE(r.emu.dsgFet());
  r.h.runFor(fw::us(2));
  EXPECT_FALSE(r.emu.dsgFet());
  EXPECT_TRUE(r.emu.safetyStatusA() & map7::bits::SafetyStatusA::scd_mask);
  r.emu.setCurrentMa(0);
  r.h.runFor(fw::s(5));
  ASSERT_TRUE(r.emu.dsgFet()) << "recovered after Recovery Time";
  r.emu.setDataMemory(map7::dm::EnabledProtectionsB.address, map7::bits::EnabledProtectionsB::hwd_mask, 1);
  r.emu.setDataMemory(map7::dm::HostWatchdogTimeout.address, 1, 1);  // 2 s
  r.read(0x12, 2);
  r.h.runFor(fw::ms(1010));
  EXPECT_TRUE(r.emu.dsgFet());
  r.h.runFor(fw::ms(1000));
  EXPECT_TRUE(r.emu.safetyStatusB() & map7::bits::SafetyB::hwd_mask);
  EXPECT_FALSE(r.emu.dsgFet());
  r.read(0x12, 2);
  EXPECT_TRUE(r.emu.dsgFet());
}

}  // namespace
