// What a scan of a BQ769x2 (BQ76952...) or BQ7690x (BQ76905/BQ76907) monitor produces: the device's own
// register image of the measurement set, typed with the generated register-map accessors.
//
// Each record is the bytes of the direct commands a scan reads, in the order the scan reads them (the
// device sends every value little-endian, and both the Cortex-M0+ and the host are little-endian, so the
// validated bytes are the record: no per-field decoding code). Fields are the generated value types:
//   m.reg.safetyStatusA.cuv(), m.reg.batteryStatus.cfgupdate(), m.reg.fetStatus.chg_fet()
// A record is written only by a scan whose every transaction validated (CRC when enabled, plausibility of
// the reserved bits and signs the device always keeps clear), and takenAt is the end of its last
// transaction. Units (integers; converters below):
//   cell voltages  mV, signed (an input with no cell can read slightly negative)
//   stack/pack/LD  BQ769x2: userV (DA Configuration[USER_VOLTS_CV]: 10 mV by default); BQ7690x stack: mV
//   current        CC2, signed userA (DA Configuration[USER_AMPS]: 1 mA by default), charge positive;
//                  at 1 mA it saturates at +-32.767 A (LibreSolar 7b0bb23): pick the unit for the pack
//   temperatures   BQ769x2: 0.1 K; BQ7690x internal: 1 degC (regmaps/README.md deviation 7), TS: counts
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "core/time.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace fw::drivers::bq769x2 {

static_assert(std::endian::native == std::endian::little, "records are the device's little-endian bytes");

namespace map = ::fw::regmap::bq769x2;
namespace map7690x = ::fw::regmap::bq7690x;

inline constexpr uint8_t kMaxCells = 16;

// The BQ769x2 scan blocks (regmaps/bq769x2/commands.yaml `blocks:`, SLUUBY2B chapter 12), in their order.
struct Bq769x2Registers {
  // 0x0A..0x11
  map::bits::PfA pfAlertA;
  map::bits::PfA pfStatusA;
  map::bits::PfB pfAlertB;
  map::bits::PfB pfStatusB;
  map::bits::PfAlertC pfAlertC;
  map::bits::PfStatusC pfStatusC;
  map::bits::PfD pfAlertD;
  map::bits::PfD pfStatusD;
  map::bits::BatteryStatus batteryStatus;  // 0x12
  int16_t cellMv[kMaxCells];               // 0x14..0x33
  int16_t stack;                           // 0x34 userV
  int16_t pack;                            // 0x36 userV
  int16_t ld;                              // 0x38 userV
  int16_t current;                         // 0x3A CC2, userA
  // 0x62..0x75
  map::bits::Alarm alarmStatus;  // latched (write 1 to clear), drives ALERT
  map::bits::Alarm alarmRaw;
  map::bits::Alarm alarmEnable;
  int16_t intTemp;  // 0x68, 0.1 K
  int16_t cfetoffTemp;
  int16_t dfetoffTemp;
  int16_t alertTemp;
  int16_t ts[3];  // TS1..TS3, 0.1 K (0 when the pin is not a thermistor input)
  // 0x02..0x07
  map::bits::SafetyA safetyAlertA;
  map::bits::SafetyA safetyStatusA;
  map::bits::SafetyB safetyAlertB;
  map::bits::SafetyB safetyStatusB;
  map::bits::SafetyAlertC safetyAlertC;
  map::bits::SafetyC safetyStatusC;
  map::bits::FetStatus fetStatus;  // 0x7F: what the FETs are doing (never the host's intent)
};
// The record is the blocks of regmaps/bq769x2/commands.yaml back to back: every field lies where its block
// (`record`) and its command's place in the block (`offset<Member>`) put it.
namespace layout769x2 {
using V = map::blocks::PfStatusAndVoltages;
using T = map::blocks::AlarmsAndTemperatures;
using S = map::blocks::Safety;
using F = map::blocks::Fets;
using R = Bq769x2Registers;
static_assert(offsetof(R, pfAlertA) == V::record + V::offsetPfAlertA);
static_assert(offsetof(R, pfStatusA) == V::record + V::offsetPfStatusA);
static_assert(offsetof(R, pfAlertB) == V::record + V::offsetPfAlertB);
static_assert(offsetof(R, pfStatusB) == V::record + V::offsetPfStatusB);
static_assert(offsetof(R, pfAlertC) == V::record + V::offsetPfAlertC);
static_assert(offsetof(R, pfStatusC) == V::record + V::offsetPfStatusC);
static_assert(offsetof(R, pfAlertD) == V::record + V::offsetPfAlertD);
static_assert(offsetof(R, pfStatusD) == V::record + V::offsetPfStatusD);
static_assert(offsetof(R, batteryStatus) == V::record + V::offsetBatteryStatus);
static_assert(offsetof(R, cellMv) == V::record + V::offsetCell1Voltage);
static_assert(offsetof(R, cellMv) + 2 * (kMaxCells - 1) == V::record + V::offsetCell16Voltage);
static_assert(offsetof(R, stack) == V::record + V::offsetStackVoltage);
static_assert(offsetof(R, pack) == V::record + V::offsetPackPinVoltage);
static_assert(offsetof(R, ld) == V::record + V::offsetLdPinVoltage);
static_assert(offsetof(R, current) == V::record + V::offsetCc2Current);
static_assert(offsetof(R, alarmStatus) == T::record + T::offsetAlarmStatus);
static_assert(offsetof(R, alarmRaw) == T::record + T::offsetAlarmRawStatus);
static_assert(offsetof(R, alarmEnable) == T::record + T::offsetAlarmEnable);
static_assert(offsetof(R, intTemp) == T::record + T::offsetIntTemperature);
static_assert(offsetof(R, cfetoffTemp) == T::record + T::offsetCfetoffTemperature);
static_assert(offsetof(R, dfetoffTemp) == T::record + T::offsetDfetoffTemperature);
static_assert(offsetof(R, alertTemp) == T::record + T::offsetAlertTemperature);
static_assert(offsetof(R, ts) == T::record + T::offsetTs1Temperature);
static_assert(offsetof(R, ts) + 4 == T::record + T::offsetTs3Temperature);
static_assert(offsetof(R, safetyAlertA) == S::record + S::offsetSafetyAlertA);
static_assert(offsetof(R, safetyStatusA) == S::record + S::offsetSafetyStatusA);
static_assert(offsetof(R, safetyAlertB) == S::record + S::offsetSafetyAlertB);
static_assert(offsetof(R, safetyStatusB) == S::record + S::offsetSafetyStatusB);
static_assert(offsetof(R, safetyAlertC) == S::record + S::offsetSafetyAlertC);
static_assert(offsetof(R, safetyStatusC) == S::record + S::offsetSafetyStatusC);
static_assert(offsetof(R, fetStatus) == F::record + F::offsetFetStatus);
static_assert(offsetof(R, fetStatus) + sizeof(R::fetStatus) == map::blocks::kRecordSize);  // then padding
}  // namespace layout769x2

// The accumulated charge a scan read (BQ769x2 DASTATUS6 / BQ7690x PASSQ result bytes 0..11: the count and
// the accumulated time, app/soc/accumulated_charge.hpp decodes them). `valid`: the subcommand's echo named it
// (the result was ready); otherwise the scan's other values stand and the charge is not read this time.
inline constexpr uint8_t kChargeBytes = 12;
struct ChargeCounter {
  uint8_t raw[kChargeBytes];
  bool valid;
};

struct Bq769x2Measurement {
  Instant takenAt{};
  Bq769x2Registers reg{};
  ChargeCounter charge{};
  // Any enabled protection or permanent-fail flag the device reports as tripped.
  bool deviceFault() const {
    return (reg.safetyStatusA.raw() | reg.safetyStatusB.raw() | reg.safetyStatusC.raw() |
            reg.pfStatusA.raw() | reg.pfStatusB.raw() | reg.pfStatusC.raw() | reg.pfStatusD.raw()) != 0;
  }
};

// The BQ7690x scan blocks (regmaps/bq7690x/commands.yaml `blocks:`, SLUUCI8/SLUUCJ0), in their order.
struct Bq7690xRegisters {
  map7690x::bits::BatteryStatus batteryStatus;  // 0x12
  int16_t cellMv[7];                            // 0x14..0x21 (cells 6-7: BQ76907 only)
  int16_t reg18;                                // 0x22 counts
  int16_t vss;                                  // 0x24 counts
  int16_t stack;                                // 0x26 mV
  int16_t intTemp;                              // 0x28 degC (see the header)
  int16_t ts;                                   // 0x2A counts
  map7690x::bits::Alarm alarmStatus;            // 0x62
  map7690x::bits::Alarm alarmRaw;
  map7690x::bits::Alarm alarmEnable;
  int16_t current;                              // 0x3A CC2, userA
  map7690x::bits::SafetyAlertA safetyAlertA;    // 0x02 (bits 1:0 reserved)
  map7690x::bits::SafetyStatusA safetyStatusA;  // 0x03 (bits 1:0 CURLATCH, REGOUT: faults)
  map7690x::bits::SafetyB safetyAlertB;         // 0x04
  map7690x::bits::SafetyB safetyStatusB;        // 0x05
};
// The record is the blocks of regmaps/bq7690x/commands.yaml back to back (as for the BQ769x2 above).
namespace layout7690x {
using V = map7690x::blocks::StatusAndVoltages;
using A = map7690x::blocks::Alarms;
using C = map7690x::blocks::Current;
using S = map7690x::blocks::Safety;
using R = Bq7690xRegisters;
static_assert(offsetof(R, batteryStatus) == V::record + V::offsetBatteryStatus);
static_assert(offsetof(R, cellMv) == V::record + V::offsetCell1Voltage);
static_assert(offsetof(R, cellMv) + 2 * 6 == V::record + V::offsetCell7Voltage);
static_assert(offsetof(R, reg18) == V::record + V::offsetReg18Voltage);
static_assert(offsetof(R, vss) == V::record + V::offsetVssVoltage);
static_assert(offsetof(R, stack) == V::record + V::offsetStackVoltage);
static_assert(offsetof(R, intTemp) == V::record + V::offsetIntTemperature);
static_assert(offsetof(R, ts) == V::record + V::offsetTsMeasurement);
static_assert(offsetof(R, alarmStatus) == A::record + A::offsetAlarmStatus);
static_assert(offsetof(R, alarmRaw) == A::record + A::offsetAlarmRawStatus);
static_assert(offsetof(R, alarmEnable) == A::record + A::offsetAlarmEnable);
static_assert(offsetof(R, current) == C::record + C::offsetCc2Current);
static_assert(offsetof(R, safetyAlertA) == S::record + S::offsetSafetyAlertA);
static_assert(offsetof(R, safetyStatusA) == S::record + S::offsetSafetyStatusA);
static_assert(offsetof(R, safetyAlertB) == S::record + S::offsetSafetyAlertB);
static_assert(offsetof(R, safetyStatusB) == S::record + S::offsetSafetyStatusB);
static_assert(offsetof(R, safetyStatusB) + sizeof(R::safetyStatusB) == map7690x::blocks::kRecordSize);
}  // namespace layout7690x

struct Bq7690xMeasurement {
  Instant takenAt{};
  Bq7690xRegisters reg{};
  ChargeCounter charge{};
  bool deviceFault() const { return (reg.safetyStatusA.raw() | reg.safetyStatusB.raw()) != 0; }
};

// Tenths of a kelvin from a temperature reading, by its descriptor's unit (K or degC) and scale: BQ769x2
// temperatures are 0.1 K (the reading itself), the BQ7690x Int Temperature whole degrees C (regmaps/README.md
// deviation 7). rawTemperature() is the inverse (what an emulator is set to). Integer factors only.
inline constexpr int32_t kZeroCelsiusDeciK = 2732;
template <class D>
constexpr int32_t deciKelvinPerLsb(D) {
  static_assert(D::unit == regmap::Unit::Kelvin || D::unit == regmap::Unit::DegreeCelsius);
  static_assert((10 * D::scale.num) % D::scale.den == 0, "a whole number of 0.1 K per LSB");
  return static_cast<int32_t>(10 * D::scale.num / D::scale.den);
}
template <class D>
constexpr int32_t deciKelvinAtZero(D) {
  return D::unit == regmap::Unit::DegreeCelsius ? kZeroCelsiusDeciK : 0;
}
template <class D>
constexpr int16_t deciKelvin(D d, int16_t raw) {
  return static_cast<int16_t>(raw * deciKelvinPerLsb(d) + deciKelvinAtZero(d));
}
template <class D>
constexpr int16_t rawTemperature(D d, int32_t deciK) {
  return static_cast<int16_t>((deciK - deciKelvinAtZero(d)) / deciKelvinPerLsb(d));
}

// Milliamps from a CC2 reading in userA: lsbTenthMilliamp is the userA LSB in 0.1 mA (1, 10, 100 or 1000
// for DA Configuration[USER_AMPS] = 0..3).
constexpr int32_t currentMa(int16_t userA, int32_t lsbTenthMilliamp = 10) {
  return static_cast<int32_t>(userA) * lsbTenthMilliamp / 10;
}
// Millivolts from a stack/pack/LD reading in userV (10 mV per LSB unless USER_VOLTS_CV is cleared).
constexpr int32_t userVoltsMv(int16_t userV, int32_t lsbMillivolt = 10) {
  return static_cast<int32_t>(userV) * lsbMillivolt;
}

}  // namespace fw::drivers::bq769x2
