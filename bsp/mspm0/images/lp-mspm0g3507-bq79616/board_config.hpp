// Board settings of the lp-mspm0g3507-bq79616 image (read by images/common/board_g3507_can.cpp). The
// UART instance and pins are chosen by the CMake cache variable BMS_BQ79616_UART (see the board header).
#pragma once

#include <cstdint>

namespace image::config {

// BQ79616 daisy-chain base link: 1 Mbaud 8N1 (TI's bq79616_uart_to_can example, MSPM0 SDK 2.09,
// ti_msp_dl_config.c; IBRD 2, FBRD 0 from 32 MHz).
inline constexpr uint32_t kBq79616Baud = 1000000;

// Devices the chain is built with (CMake BMS_BQ79616_DEVICES, default 2 as in TI's example). Bring-up
// discovers the devices that answer and reports a mismatch; it does not trust this number blindly.
#ifndef BMS_BQ79616_DEVICES
#define BMS_BQ79616_DEVICES 2
#endif
inline constexpr uint8_t kBq79616Devices = BMS_BQ79616_DEVICES;
static_assert(kBq79616Devices >= 1 && kBq79616Devices <= 64, "BMS_BQ79616_DEVICES must be 1..64");

}  // namespace image::config
