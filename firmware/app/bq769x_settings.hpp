// The CONFIG_UPDATE tables the BQ769x2-family images apply at start-up (compared first: written only when the
// device differs). Values are in range by construction: setting() refuses a value outside the TRM's limits
// at compile time.
//
// BQ76952 (seed 000's LP-MSPM0L1306 + BQ76952EVM set-up, SLAAEB3 / SLUUBY2B): the pin and regulator
// configuration TI's example writes, 16 cells, the protections TI enables, and Li-ion thresholds (TI's
// example uses the EVM's 0.75 V simulation thresholds, which are outside the TRM ranges). The device's own
// limits sit just above the firmware's (default_limits.hpp: 4.25 V / 2.70 V), as the backstop. The alarm
// mask keeps ALERT to safety and permanent-fail events (no scan-complete alerts), so ALERT means a fault.
// BQ76907 (seed 004, SLUAAM4 / SLUUCJ0): 7 cells, COV/CUV/SCD/OCD1 enabled.
#pragma once

#include "drivers/bq769x2/monitor.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace fw::app {

namespace settings_detail {
namespace m2 = ::fw::regmap::bq769x2;
namespace m7 = ::fw::regmap::bq7690x;
using drivers::bq769x2::setting;
}  // namespace settings_detail

inline constexpr drivers::bq769x2::Setting kBq76952Settings[] = {
    settings_detail::setting(settings_detail::m2::dm::PowerConfig, 0x2D80),
    settings_detail::setting(settings_detail::m2::dm::Reg0Config, 0x01),
    settings_detail::setting(settings_detail::m2::dm::Reg12Config, 0x0D),
    settings_detail::setting(settings_detail::m2::dm::DfetoffPinConfig, 0x42),
    settings_detail::setting(settings_detail::m2::dm::AlertPinConfig, 0x2A),
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
};

inline constexpr drivers::bq769x2::Setting kBq76907Settings[] = {
    settings_detail::setting(settings_detail::m7::dm::EnabledProtectionsA,
                             settings_detail::m7::bits::EnabledProtectionsA::fromRaw(0xE1)),
    settings_detail::setting(settings_detail::m7::dm::VcellMode, uint8_t{0x07}),
};

}  // namespace fw::app
