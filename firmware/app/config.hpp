// Build options of the application (firmware/app): every option's default, meaning and dependencies. An image
// sets its values in bsp/mspm0/images/<preset>/options.cmake; the host uses these defaults.
//
// Not moved here yet (their headers were being changed on another branch, issue 16): FW_PROTECTION_DELAYS
// (app/protection.hpp), FW_PROTECTION_LOG_SIZE and FW_PROTECTION_CLEAR_LATCHED (app/protection_task.hpp),
// FW_PACK_MAX_BOARDS (app/pack_view.hpp), FW_PUBLISH_LEVEL (app/publish_status.hpp), FW_CAN_TI_LAYOUT
// (app/can_bits.hpp): each is documented with its default next to its #ifndef there.
#pragma once

// BQ769x2-family application (app/bq769x_app.hpp).
// The start-up CONFIG_UPDATE of the settings table (compared first, written only where the device differs).
// Every image ships with it: without it the BQ76952's ALERT pin stays unconfigured and the BQ76907 ignores
// host FET-off commands (issue 12). Needs the driver's configuration paths (FW_BQ769X_CONFIG_PATHS).
#ifndef FW_BQ769X_CONFIG_UPDATE
#define FW_BQ769X_CONFIG_UPDATE 1
#endif
// Bq769xAppConfig::faultIndicator, the fault output pin. 0 where the board has none (the L1306).
#ifndef FW_BQ769X_FAULT_INDICATOR
#define FW_BQ769X_FAULT_INDICATOR 1
#endif
