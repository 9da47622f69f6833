// Board settings of the lp-mspm0l1306-bq76907 image (read by images/common/board_l1306_i2c_slcan.cpp).
#pragma once

#include <cstdint>

namespace image::config {

// BQ76907 / BQ76905 on I2C0: fast mode (the BQ7690x supports 400 kHz). The device may stretch SCL up to 4 ms;
// a longer stretch is a stuck bus. i2cTiming() makes timeout A that long, counted as TI counts
// TIMEOUT_CTL.TCNTLA (i2c_timing.hpp): 84 counts at 32 MHz (TPR 7) = 4.03 ms.
inline constexpr uint32_t kI2cBitRate = 400000;
inline constexpr uint32_t kI2cStretchLimitUs = 4000;
// XDS110 back-channel UART rate for SLCAN text.
inline constexpr uint32_t kSlcanBaud = 115200;

}  // namespace image::config
