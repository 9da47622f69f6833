// Board settings of the lp-mspm0g3507-bq76907 image (read by images/common/board_g3507_can.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ76907 on I2C0: fast mode, 400 kHz at most (SLUSE97); a stretch longer than 4 ms is a stuck bus.
inline constexpr uint32_t kI2cBitRate = 400000;
inline constexpr uint32_t kI2cStretchLimitUs = 4000;

}  // namespace image::config
