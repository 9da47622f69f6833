// The board of this image: LP-MSPM0G3507, BQ79616 chain on a UART, CAN out (see the included header).
#pragma once

#include "common/board_g3507_can.hpp"
