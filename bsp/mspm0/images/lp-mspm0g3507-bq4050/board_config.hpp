// Board settings of the lp-mspm0g3507-bq4050 image (read by images/common/board_g3507_can.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ4050 on SMBus: 100 kHz (SMBus 2.0 standard mode; the seed 003 notes slow SMBus timing). SMBus lets a
// device stretch the clock up to 25 ms (tTIMEOUT). i2cTiming() makes timeout A at least that long under both
// of TI's readings of TIMEOUT_CTL.TCNTLA (i2c_timing.hpp); the header's 520 clocks per count need the
// functional clock divided by 8 (4 MHz, TPR 3): 193 counts = 25.1 ms, and 37.1 ms under the TRM's
// 16 x (1 + TPR) x 12 clocks per count.
inline constexpr uint32_t kI2cBitRate = 100000;
inline constexpr uint32_t kI2cStretchLimitUs = 25000;

}  // namespace image::config
