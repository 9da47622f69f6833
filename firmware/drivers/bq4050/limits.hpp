// BQ4050 plausibility limits: the range a raw SBS word can take on a working BQ4050 pack.
//
// Contract
// - plausibleWord(cmd, raw) is true when `raw`, read from SBS command `cmd` as an SMBus word, lies inside the
//   range in the table below (inclusive); commands without an entry accept every value. Signed commands
//   (Current) compare the two's-complement value. BatteryStatus must also have its reserved bits clear.
// - Pure function, no state, callable from any context. The driver never publishes a word that fails it,
//   with or without PEC (a PEC only proves the bytes arrived as sent, not that the gauge sent sense).
//
// The table (raw units; sources in limits.cpp):
//   0x08 Temperature            2231..4231 (0.1 K: -50.0 .. +150.0 degC)
//   0x09 Voltage                0..20000 mV (4 series cells x 5000 mV)
//   0x0A Current                -32768..32767 mA (the whole I2 range: no value can be excluded)
//   0x0D RelativeStateOfCharge  0..100 % (the register map's SBS 1.1 limits)
//   0x0F RemainingCapacity      0..32767 (mAh or 10 mWh)
//   0x10 FullChargeCapacity     0..32767 (mAh or 10 mWh)
//   0x16 BatteryStatus          reserved bits 13 and 10 clear
//   0x3C..0x3F CellVoltage4..1  0..5000 mV
#pragma once

#include <cstdint>

namespace fw::drivers::bq4050 {

bool plausibleWord(uint8_t cmd, uint16_t raw);

}  // namespace fw::drivers::bq4050
