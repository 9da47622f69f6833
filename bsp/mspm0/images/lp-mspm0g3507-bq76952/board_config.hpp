// Board settings of the lp-mspm0g3507-bq76952 image (read by images/common/board_g3507_can.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ76952 on I2C0: fast mode. Clock stretching is limited to 4 ms (the longest timeout A reaches with the
// undivided 32 MHz I2C clock: 255 x 520 / 32 MHz = 4.1 ms); a longer stretch is a stuck bus.
inline constexpr uint32_t kI2cBitRate = 400000;
inline constexpr uint32_t kI2cStretchLimitUs = 4000;

}  // namespace image::config
