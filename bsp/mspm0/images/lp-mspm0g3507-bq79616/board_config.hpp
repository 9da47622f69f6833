// Board settings of the lp-mspm0g3507-bq79616 image (read by images/common/board_g3507_uart_can.cpp). The
// UART instance and pins are chosen by the CMake cache variable BMS_BQ79616_UART (see the board header).
#pragma once

#include <cstdint>

namespace image::config {

// BQ79616 daisy-chain base link: 1 Mbaud 8N1 (bq79616-protocol.md section 1; IBRD 2, FBRD 0 from 32 MHz).
inline constexpr uint32_t kBq79616Baud = 1000000;

}  // namespace image::config
