// Board settings of the lp-mspm0g3507-bq4050 image (read by images/common/board_g3507_can.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ4050 on SMBus: 100 kHz (SMBus 2.0 standard mode; the seed 003 notes slow SMBus timing). SMBus lets a
// device stretch the clock up to 25 ms and a host must time out by 35 ms (tTIMEOUT 25..35 ms). i2cTiming()
// makes timeout A 131 counts of 16 x (1 + TPR) x 12 clocks at the undivided 32 MHz clock (TPR 31), counted
// as TI counts TIMEOUT_CTL.TCNTLA (i2c_timing.hpp): 25.15 ms.
inline constexpr uint32_t kI2cBitRate = 100000;
inline constexpr uint32_t kI2cStretchLimitUs = 25000;

}  // namespace image::config
