// Build options of the MSPM0 board support and the images' boards (bsp/mspm0): every option's default,
// meaning and dependencies. An image sets its values in images/<preset>/options.cmake.
#pragma once

// SMBus PEC and block reads in the I2C driver (i2c.hpp). 0 saves their code where no driver sets
// I2cTransaction::pec or ::blockRead (the BQ769x2-family images): PECCTL keeps its reset value and a
// transaction asking for PEC or a block read is refused with InvalidArgument rather than sent without it.
#ifndef BSP_I2C_PEC
#define BSP_I2C_PEC 1
#endif

// I2C transaction lists longer than one (i2c.hpp). 0 saves the list handling where every driver starts one
// transaction at a time (every image's): start() then refuses a longer list with InvalidArgument.
#ifndef BSP_I2C_LISTS
#define BSP_I2C_LISTS 1
#endif

// CAN reception (mcan.hpp). 0 saves the RX path where the application only transmits (the G3507 images): the
// global filter rejects every frame and receive() returns false.
#ifndef BSP_MCAN_RX
#define BSP_MCAN_RX 1
#endif

// The idle's power policy (power_policy.hpp, L1306 boards): 1 sleeps in STANDBY1 between scans, with the
// scheduler's clock corrected from an LFCLK timer (TIMG1); 0 keeps the plain SLEEP0 of every idle.
#ifndef BSP_DEEP_IDLE
#define BSP_DEEP_IDLE 0
#endif

// The LaunchPad's LED and button S2 (images/common/board_*.hpp): built only for an application that uses them
// (none does yet; 1 builds both drivers into the board).
#ifndef BMS_BOARD_LED_BUTTON
#define BMS_BOARD_LED_BUTTON 0
#endif

// The G3507 board's monitor link (images/common/board_g3507_can.hpp): 0 I2C0 (BQ4050, BQ76952), 1 a BQ79616
// daisy chain on a UART (the BQ79616 image).
#ifndef BMS_BOARD_MONITOR_ON_UART
#define BMS_BOARD_MONITOR_ON_UART 0
#endif

// Two choices of the lp-mspm0g3507-bq79616 build are CMake cache variables given at configure time, not image
// options: BMS_BQ79616_DEVICES (the chain length, images/lp-mspm0g3507-bq79616/board_config.hpp) and
// BMS_BQ79616_UART (the UART and pins, images/images.cmake).
