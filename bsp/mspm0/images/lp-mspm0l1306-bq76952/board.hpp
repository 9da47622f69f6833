// The board of this image: LP-MSPM0L1306, BQ76952 on I2C0, SLCAN on UART0 (see the included header).
#pragma once

#include "common/board_l1306_i2c_slcan.hpp"
