// The CONFIG_UPDATE tables the BQ769x2-family images apply at start-up (compared first: written only when the
// device differs). Values are in range by construction: setting() refuses a value outside the TRM's limits
// at compile time.
//
// BQ76952 (seed 000's LP-MSPM0L1306 + BQ76952EVM set-up, SLAAEB3 / SLUUBY2B): the pin and regulator
// configuration TI's example writes, 16 cells, the protections TI enables, and Li-ion thresholds (TI's
// example uses the EVM's 0.75 V simulation thresholds, which are outside the TRM ranges). The device's own
// limits sit just above the firmware's (default_limits.hpp: 4.25 V / 2.70 V), as the backstop. The alarm
// mask keeps ALERT to safety and permanent-fail events (no scan-complete alerts), so ALERT means a fault.
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
// configuration: it is asserted low (SLUUCJ0 Alarm Status).
// Balancing (both families): Balancing Configuration written explicitly with host commands accepted and no
// automatic balancing (BQ769x2 0x00, SLUUBY2B; BQ7690x 0x02 = CBDLY 1 ms, SLUUCI8: the firmware's policy
// decides, app/balancing); on the BQ769x2 Cell Balance Max Cells = the policy's limit (the device refuses
// more, E2E 969824) and the device's own balancing temperature limits (-20 / 60 degC cell, 70 degC die, the
// map's defaults, `unverified`: written so they hold whatever the device shipped with), outside the policy's
// 0 / 45 / 65 degC (app/balancing/balancing_config.hpp) as the backstop.
#pragma once

#include <array>
#include <cstdint>

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

constexpr std::array<drivers::bq769x2::Setting, 5> bq7690xSettings(uint8_t cells) {
  return {setting(m7::dm::EnabledProtectionsA, m7::bits::EnabledProtectionsA::fromRaw(0xE1)),
          setting(m7::dm::VcellMode, cells), setting(m7::dm::FetOptions, kBq7690xFetOptions),
          setting(m7::dm::DefaultAlarmMask, kBq7690xAlarmMask.raw()),
          setting(m7::dm::BalancingConfiguration, m7::bits::BalancingConfiguration{}.with_cbdly(1))};
}
}  // namespace settings_detail

inline constexpr drivers::bq769x2::Setting kBq76952Settings[] = {
    settings_detail::setting(settings_detail::m2::dm::PowerConfig, 0x2D80),
    settings_detail::setting(settings_detail::m2::dm::Reg0Config, 0x01),
    settings_detail::setting(settings_detail::m2::dm::Reg12Config, 0x0D),
    settings_detail::setting(settings_detail::m2::dm::DfetoffPinConfig, 0x42),
    settings_detail::setting(settings_detail::m2::dm::AlertPinConfig,
                             settings_detail::kAlertActiveLowOpenDrain),
    settings_detail::setting(settings_detail::m2::dm::Ts1Config, 0x07),
    settings_detail::setting(settings_detail::m2::dm::Ts3Config, 0x0F),
    settings_detail::setting(settings_detail::m2::dm::HdqPinConfig, 0x00),
    settings_detail::setting(settings_detail::m2::dm::VCellMode, 0xFFFF),
    settings_detail::setting(settings_detail::m2::dm::EnabledProtectionsA,
                             settings_detail::m2::bits::SafetyA::fromRaw(0xBC)),
    settings_detail::setting(settings_detail::m2::dm::EnabledProtectionsB,
                             settings_detail::m2::bits::SafetyB::fromRaw(0xF7)),
    settings_detail::setting(settings_detail::m2::dm::DefaultAlarmMask, 0xF800),
    settings_detail::setting(settings_detail::m2::dm::CuvThreshold, 52),  // 52 x 50.6 mV = 2631 mV
    settings_detail::setting(settings_detail::m2::dm::CovThreshold, 85),  // 85 x 50.6 mV = 4301 mV
    settings_detail::setting(settings_detail::m2::dm::OccThreshold, 10),  // 20 mV across the sense resistor
    settings_detail::setting(settings_detail::m2::dm::Ocd1Threshold, 50),
    settings_detail::setting(settings_detail::m2::dm::BalancingConfiguration,
                             settings_detail::m2::bits::BalancingConfiguration{}),
    settings_detail::setting(settings_detail::m2::dm::CellBalanceMaxCells, kBq769x2BalanceCells),
    settings_detail::setting(settings_detail::m2::dm::MinCellTemp, -20),
    settings_detail::setting(settings_detail::m2::dm::MaxCellTemp, 60),
    settings_detail::setting(settings_detail::m2::dm::MaxInternalTemp, 70),
};

inline constexpr auto kBq76907Settings = settings_detail::bq7690xSettings(7);
inline constexpr auto kBq76905Settings = settings_detail::bq7690xSettings(5);

}  // namespace fw::app
