// The board of this image: LP-MSPM0G3507, BQ4050 on SMBus (I2C0 + PEC), CAN out (see the included header).
#pragma once

#include "common/board_g3507_can.hpp"
