// The board of this image: LP-MSPM0G3507, BQ76907 on I2C0, CAN out (see the included header).
#pragma once

#include "common/board_g3507_can.hpp"
