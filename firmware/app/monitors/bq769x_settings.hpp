// The CONFIG_UPDATE tables the BQ769x2-family images apply at start-up (compared first: written only when the
// device differs). Values are in range by construction: setting() refuses a value outside the TRM's limits
// at compile time.
//
// Each device protection the table enables gets its threshold and delay written explicitly, outside the
// firmware limit it backs up (app/protection/default_limits.hpp), so the firmware acts first on every normal
// limit and the device is the backstop (tests/app/backstop_test.cpp checks the ordering and that each value
// is a legal TRM value). Current thresholds are voltages across the sense resistor: the EVMs' 1 mOhm shunt
// (BQ76952EVM, BQ76907EVM: kShuntMicroOhm), so 1 mV is 1 A. Another shunt needs new current thresholds.
//
// BQ76952 (seed 000's LP-MSPM0L1306 + BQ76952EVM set-up, SLAAEB3 / SLUUBY2B): the pin and regulator
// configuration TI's example writes, 16 cells, the protections TI enables (A: SCD, OCD1, OCC, COV, CUV; B:
// OTF, OTINT, OTD, OTC, UTINT, UTD, UTC) and C: SCDL and the host watchdog, with:
//   COV 85 x 50.6 = 4301 mV, CUV 52 x 50.6 = 2631 mV, each after 3.3 ms x (2 + 74) = 250.8 ms (SLUUBY2B 5.2):
//     the firmware's 4250 / 2700 mV act first;
//   OCC 12 x 2 mV = 24 A and OCD1 20 x 2 mV = 40 A, after 3.3 ms x (2 + 4) = 19.8 ms (SLUUBY2B 5.2, OCC and
//     OCD1 Delay): the firmware's 20 A / -30 A act first;
//   SCD 100 mV = 100 A after (3 - 1) x 15 us = 30 us and SCDL Latch Limit 1, as TI's bq769x2_control_i2c
//     start-up writes them (SLUUBY2B Protections:SCD:Delay; without them SCD trips at its 10 mV default: a
//     10 A load opens DSG, issue 23). The latch is enabled (Enabled Protections C[SCDL]) and recovers with
//     charge current (Protection Configuration[SCDL_CURR_RECOV] bit 10, SLUUCG7 / SLUUCF2C), as the
//     firmware's own discharge over-current does;
//   OTC 55, OTD 65, OTF 80, OTINT 85, UTC -5, UTD -25, UTINT -25 degC, 2 s each: outside the firmware's
//     45 / 60 (charge / discharge) and 0 / -20 degC. TS1 is the cell thermistor (cell protections), TS3 the
//     FET one (OTF), the internal sensor OTINT/UTINT (TS config OPT[1:0], SLUUBY1B TS1 Config); the
//     firmware's limits look at all three;
//   the host watchdog (Protections:HWD:Delay 2 s): the device opens both FETs (CHG/DSG FET Protections
//     C[HWDF], default) when the MCU has not talked to it for 2 s, and lets them on again when it does
//     (SLUUBY2B 5.2 "Host Watchdog", SLUUCF2C the same);
//   CFETOFF and DFETOFF as their pin functions, active-high, each its own FET (0x02: PIN_FXN 2, OPT5 = 0
//     active-high, OPT4 = 0 not BOTHOFF; SLUAAQ5 "DFETOFF Pin Config[OPT5]", TI's example comments 0x02 /
//     0x42 for DSG only / both): the MCU drives them with protection's request, a path off without I2C.
// The alarm mask keeps ALERT to safety and permanent-fail events (no scan-complete alerts), so ALERT means a
// fault.
// ALERT Pin Config is 0x82, not TI's 0x2A: ALERT function (PIN_FXN = 2), active-low (OPT5), tri-stated
// while deasserted (OPT1 = 0, so no REG1 drive, OPT3 = 0) and no weak pull-up or pull-down (OPT2, OPT0): an
// open-drain output that the MCU pin's pull-up holds high and the device pulls low on an alarm, a falling
// edge (SLUUCG7 / SLUUBY1B ALERT Pin Config; TI's 0x2A drives it active-high from REG1, which a pulled-up
// falling-edge input never sees assert).
// BQ7690x (seed 004, SLUAAM4 / SLUUCJ0 / SLUUCI8): the cell count (Vcell Mode is a count), COV/CUV/SCD/
// REGOUT enabled, FET Options with HOST_FETOFF_EN (bit 6) added to its default 0x18 so FET Control's OFF
// bits act at all (SLUUCJ0 FET Control, SLUUCI8 FET Options: without it host FET-off is ignored), and the
// same ALERT policy as the BQ76952 (Alarm Enable loads from Default Alarm Mask at reset and at the exit of
// CONFIG_UPDATE, SLUUCJ0): safety status A/B and safety alerts A/B. The BQ7690x ALERT pin itself needs no
// configuration: it is asserted low (SLUUCJ0 Alarm Status). Its protections: COV 4301 mV and CUV 2600 mV
// (plain mV; SLUUCY8, the BQ77307 built on the same core, documents 0..5500 mV) after 10 ADSCAN intervals
// (SLUUCI8), SCD 100 mV (setting 5 of SLUUCJ0 Table 6-9: 100 A on the 1 mOhm shunt) after 45..60 us
// (setting 3, Table 6-10), and the host watchdog (Enabled Protections B[HWD], Host Watchdog Timeout code 1 =
// 2 s, SLUUCJ0 6.15: the device opens DSG, DSG FET Protections A[HWD]). The BQ7690x has no FET-off pins.
// Balancing (both families): Balancing Configuration written explicitly with host commands accepted and no
// automatic balancing (BQ769x2 0x00, SLUUBY2B; BQ7690x 0x02 = CBDLY 1 ms, SLUUCI8: the firmware's policy
// decides, app/balancing); on the BQ769x2 Cell Balance Max Cells = the policy's limit (the device refuses
// more, E2E 969824) and the device's own balancing temperature limits (-20 / 60 degC cell, 70 degC die, the
// map's defaults, `unverified`: written so they hold whatever the device shipped with), outside the policy's
// 0 / 45 / 65 degC (app/balancing/balancing_config.hpp) as the backstop.
#pragma once

#include <array>
#include <cstdint>
#include <iterator>

#include "drivers/bq769x2/monitor.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace fw::app {

// Cells balanced at once. BQ769x2: 4, written to Cell Balance Max Cells (default 1, `unverified`), which the
// device enforces (E2E 969824; LibreSolar's default max-balanced-cells is 4 too); 4 x ~54 mA through the
// internal FETs. BQ7690x: 3; TI leaves the number to the host to limit the dissipation (SLUAAP7 section 3).
inline constexpr uint8_t kBq769x2BalanceCells = 4;
inline constexpr uint8_t kBq7690xBalanceCells = 3;

namespace settings_detail {
namespace m2 = ::fw::regmap::bq769x2;
namespace m7 = ::fw::regmap::bq7690x;
using drivers::bq769x2::setting;

inline constexpr m2::bits::AlertPinConfig kAlertActiveLowOpenDrain =
    m2::bits::AlertPinConfig{}.with_opt5(true).with_pin_fxn(2);
static_assert(kAlertActiveLowOpenDrain.raw() == 0x82);

inline constexpr m7::bits::Alarm kBq7690xAlarmMask =
    m7::bits::Alarm{}.with_ssa(true).with_ssb(true).with_saa(true).with_sab(true);
inline constexpr m7::bits::FetOptions kBq7690xFetOptions =
    m7::dm::FetOptions.defaultValue().with_host_fetoff_en(true);
static_assert(kBq7690xFetOptions.raw() == 0x58);
inline constexpr m7::bits::EnabledProtectionsB kBq7690xProtectionsB =
    m7::bits::EnabledProtectionsB{}.with_hwd(true);

constexpr std::array<drivers::bq769x2::Setting, 13> bq7690xSettings(uint8_t cells) {
  return {setting(m7::dm::EnabledProtectionsA, m7::bits::EnabledProtectionsA::fromRaw(0xE1)),
          setting(m7::dm::EnabledProtectionsB, kBq7690xProtectionsB),
          setting(m7::dm::VcellMode, cells),
          setting(m7::dm::FetOptions, kBq7690xFetOptions),
          setting(m7::dm::DefaultAlarmMask, kBq7690xAlarmMask.raw()),
          setting(m7::dm::HostWatchdogTimeout, 1),                    // code 1: 2 s
          setting(m7::dm::CellOvervoltageProtectionThreshold, 4301),  // as the BQ76952 (85 x 50.6 mV)
          setting(m7::dm::CellOvervoltageProtectionDelay, 10),
          setting(m7::dm::CellUndervoltageProtectionThreshold, 2600),
          setting(m7::dm::CellUndervoltageProtectionDelay, 10),
          setting(m7::dm::ShortCircuitInDischargeProtectionThreshold, 5),  // 100 mV
          setting(m7::dm::ShortCircuitInDischargeProtectionDelay, 3),      // 45..60 us
          setting(m7::dm::BalancingConfiguration, m7::bits::BalancingConfiguration{}.with_cbdly(1))};
}

// BQ76952 Enabled Protections (SLUUBY2B Settings:Protection): A SCD, OCD1, OCC, COV, CUV; B OTF, OTINT, OTD,
// OTC, UTINT, UTD, UTC (TI's 0xBC / 0xF7); C SCDL and HWDF.
inline constexpr m2::bits::SafetyA kBq76952ProtectionsA = m2::bits::SafetyA::fromRaw(0xBC);
inline constexpr m2::bits::SafetyB kBq76952ProtectionsB = m2::bits::SafetyB::fromRaw(0xF7);
inline constexpr m2::bits::SafetyC kBq76952ProtectionsC = m2::bits::SafetyC{}.with_scdl(true).with_hwdf(true);
static_assert(kBq76952ProtectionsC.raw() == 0x42);
// Protection Configuration: the default 0x0002 (PF_FETS) with SCDL_CURR_RECOV (bit 10).
inline constexpr uint16_t kBq76952ProtectionConfiguration = 0x0402;
// CFETOFF / DFETOFF Pin Config: the pin's FET-off function, active-high, that FET only.
inline constexpr uint8_t kFetOffPinActiveHigh = 0x02;
}  // namespace settings_detail

// Sense resistor of the EVMs the images are set up for (BQ76952EVM, BQ76907EVM).
inline constexpr uint32_t kShuntMicroOhm = 1000;

inline constexpr drivers::bq769x2::Setting kBq76952Settings[] = {
    settings_detail::setting(settings_detail::m2::dm::PowerConfig, 0x2D80),
    settings_detail::setting(settings_detail::m2::dm::Reg0Config, 0x01),
    settings_detail::setting(settings_detail::m2::dm::Reg12Config, 0x0D),
    settings_detail::setting(settings_detail::m2::dm::CfetoffPinConfig,
                             settings_detail::kFetOffPinActiveHigh),
    settings_detail::setting(settings_detail::m2::dm::DfetoffPinConfig,
                             settings_detail::kFetOffPinActiveHigh),
    settings_detail::setting(settings_detail::m2::dm::AlertPinConfig,
                             settings_detail::kAlertActiveLowOpenDrain),
    settings_detail::setting(settings_detail::m2::dm::Ts1Config, 0x07),
    settings_detail::setting(settings_detail::m2::dm::Ts3Config, 0x0F),
    settings_detail::setting(settings_detail::m2::dm::HdqPinConfig, 0x00),
    settings_detail::setting(settings_detail::m2::dm::VCellMode, 0xFFFF),
    settings_detail::setting(settings_detail::m2::dm::EnabledProtectionsA,
                             settings_detail::kBq76952ProtectionsA),
    settings_detail::setting(settings_detail::m2::dm::EnabledProtectionsB,
                             settings_detail::kBq76952ProtectionsB),
    settings_detail::setting(settings_detail::m2::dm::EnabledProtectionsC,
                             settings_detail::kBq76952ProtectionsC),
    settings_detail::setting(settings_detail::m2::dm::ProtectionConfiguration,
                             settings_detail::kBq76952ProtectionConfiguration),
    settings_detail::setting(settings_detail::m2::dm::DefaultAlarmMask, 0xF800),
    settings_detail::setting(settings_detail::m2::dm::CovThreshold, 85),  // 85 x 50.6 mV = 4301 mV
    settings_detail::setting(settings_detail::m2::dm::CovDelay, 74),      // 3.3 ms x (2 + 74) = 250.8 ms
    settings_detail::setting(settings_detail::m2::dm::CuvThreshold, 52),  // 52 x 50.6 mV = 2631 mV
    settings_detail::setting(settings_detail::m2::dm::CuvDelay, 74),
    settings_detail::setting(settings_detail::m2::dm::OccThreshold, 12),   // 24 mV: 24 A
    settings_detail::setting(settings_detail::m2::dm::OccDelay, 4),        // 3.3 ms x (2 + 4) = 19.8 ms
    settings_detail::setting(settings_detail::m2::dm::Ocd1Threshold, 20),  // 40 mV: 40 A
    settings_detail::setting(settings_detail::m2::dm::Ocd1Delay, 4),
    settings_detail::setting(settings_detail::m2::dm::ScdThreshold,
                             settings_detail::m2::enums::ScdThreshold::At100mV),  // 100 A
    settings_detail::setting(settings_detail::m2::dm::ScdDelay, 3),               // (3 - 1) x 15 us = 30 us
    settings_detail::setting(settings_detail::m2::dm::ScdlLatchLimit, 1),
    settings_detail::setting(settings_detail::m2::dm::OtcThreshold, 55),
    settings_detail::setting(settings_detail::m2::dm::OtcDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::OtdThreshold, 65),
    settings_detail::setting(settings_detail::m2::dm::OtdDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::OtfThreshold, 80),
    settings_detail::setting(settings_detail::m2::dm::OtfDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::OtintThreshold, 85),
    settings_detail::setting(settings_detail::m2::dm::OtintDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::UtcThreshold, -5),
    settings_detail::setting(settings_detail::m2::dm::UtcDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::UtdThreshold, -25),
    settings_detail::setting(settings_detail::m2::dm::UtdDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::UtintThreshold, -25),
    settings_detail::setting(settings_detail::m2::dm::UtintDelay, 2),
    settings_detail::setting(settings_detail::m2::dm::HwdDelay, 2),  // s
    settings_detail::setting(settings_detail::m2::dm::BalancingConfiguration,
                             settings_detail::m2::bits::BalancingConfiguration{}),
    settings_detail::setting(settings_detail::m2::dm::CellBalanceMaxCells, kBq769x2BalanceCells),
    settings_detail::setting(settings_detail::m2::dm::MinCellTemp, -20),
    settings_detail::setting(settings_detail::m2::dm::MaxCellTemp, 60),
    settings_detail::setting(settings_detail::m2::dm::MaxInternalTemp, 70),
};
static_assert(std::size(kBq76952Settings) <= drivers::bq769x2::kMaxSettings);

inline constexpr auto kBq76907Settings = settings_detail::bq7690xSettings(7);
inline constexpr auto kBq76905Settings = settings_detail::bq7690xSettings(5);

}  // namespace fw::app
