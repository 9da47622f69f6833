// Board settings of the lp-mspm0l1306-bq76907 image (read by images/common/board_l1306_i2c_slcan.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ76907 / BQ76905 on I2C0: fast mode (the BQ7690x supports 400 kHz). Clock stretching is limited to 4 ms
// (the longest timeout A reaches with the undivided 32 MHz I2C clock: 255 x 520 / 32 MHz = 4.1 ms); a longer
// stretch is a stuck bus.
inline constexpr uint32_t kI2cBitRate = 400000;
inline constexpr uint32_t kI2cStretchLimitUs = 4000;
// XDS110 back-channel UART rate for SLCAN text.
inline constexpr uint32_t kSlcanBaud = 115200;

}  // namespace image::config
