// Plausibility limits of BQ4050 SBS words (contract in limits.hpp).
//
// Why these ranges: each one is the widest range a working BQ4050 pack can report, so a legitimate reading is
// never refused, while the two corruptions seen in the field (seed 003: the second byte's top bit stuck high,
// which adds 32768; and an all-ones 0xFFFF word) fall outside wherever the quantity allows it.
//   Temperature  SBS 1.1 Temperature() is 0.1 K over 0..65535; -50 degC .. +150 degC brackets the gauge's
//                -40..85 degC operating range (datasheet SLUSC67A, recommended operating conditions) and any
//                thermistor reading of a pack that can still run.
//   Voltage      SBS 1.1 Voltage() in mV. The BQ4050 gauges 1 to 4 series cells (SLUSC67A title), each on a
//                0..5 V cell input, so the pack reads at most 20000 mV.
//   CellVoltageN 0..5000 mV for the same reason (0x3C..0x3F are the gauge's extensions, SLUUAQ3A SBS table).
//   RSOC         0..100 %, the register map's SBS 1.1 RelativeStateOfCharge() limits (descriptor min/max).
//   Capacities   SBS 1.1 RemainingCapacity()/FullChargeCapacity() allow 0..65535, but the gauge's design and
//                learned capacities are I2 data-flash values capped at 32767 (BQ40zxy family "Design Capacity
//                mAh", I2, max 32767, SLUUCN4A), and a CEDV gauge never reports more than it learned.
//   BatteryStatus  bits 13 and 10 are reserved in SBS 1.1 BatteryStatus() (the register map's field mask).
// Current (I2) and the run times (65535 = "not applicable" in SBS 1.1) can take every value: only the
// confirming re-read protects them (gauge.cpp).
#include "drivers/bq4050/limits.hpp"

#include "regmap/bq4050.hpp"

namespace fw::drivers::bq4050 {

namespace {

namespace sbs = regmap::bq4050::sbs;

struct Limit {
  uint8_t first;  // commands first..last share the range
  uint8_t last;
  uint16_t lo;
  uint16_t hi;
};

constexpr Limit kLimits[] = {
    {regmap::code8(sbs::Temperature), regmap::code8(sbs::Temperature), 2231, 4231},
    {regmap::code8(sbs::Voltage), regmap::code8(sbs::Voltage), 0, 20000},
    {regmap::code8(sbs::RelativeStateOfCharge), regmap::code8(sbs::RelativeStateOfCharge),
     static_cast<uint16_t>(sbs::RelativeStateOfCharge.spec.min),
     static_cast<uint16_t>(sbs::RelativeStateOfCharge.spec.max)},
    {regmap::code8(sbs::RemainingCapacity), regmap::code8(sbs::FullChargeCapacity), 0, 32767},
    {regmap::code8(sbs::CellVoltage4), regmap::code8(sbs::CellVoltage1), 0, 5000},
};

static_assert(sbs::RelativeStateOfCharge.hasMin && sbs::RelativeStateOfCharge.hasMax,
              "the register map carries the SBS 1.1 RSOC range");
static_assert(regmap::code8(sbs::FullChargeCapacity) == regmap::code8(sbs::RemainingCapacity) + 1);
static_assert(regmap::code8(sbs::CellVoltage1) == regmap::code8(sbs::CellVoltage4) + 3);

}  // namespace

bool plausibleWord(uint8_t cmd, uint16_t raw) {
  if (cmd == regmap::code8(sbs::BatteryStatus)) {
    return (raw & ~regmap::bq4050::bits::BatteryStatus::fields_mask) == 0;
  }
  for (const Limit& l : kLimits) {
    if (cmd >= l.first && cmd <= l.last) return raw >= l.lo && raw <= l.hi;
  }
  return true;
}

}  // namespace fw::drivers::bq4050
