// Board settings of the lp-mspm0g3507-bq4050 image (read by images/common/board_g3507_can.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ4050 on SMBus: 100 kHz (SMBus 2.0 standard mode; the seed 003 notes slow SMBus timing). SMBus lets a
// device stretch the clock up to 25 ms (tTIMEOUT); the I2C timeout A then needs the functional clock
// divided by 8 (4 MHz: 520 / 4 MHz = 130 us per count, 193 counts), chosen by i2cTiming().
inline constexpr uint32_t kI2cBitRate = 100000;
inline constexpr uint32_t kI2cStretchLimitUs = 25000;

}  // namespace image::config
