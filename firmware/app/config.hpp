// Build options of the application (firmware/app): every option's default, meaning and dependencies. An image
// sets its values in bsp/mspm0/images/<preset>/options.cmake; the host uses these defaults, and the host
// tests and bms-sim build each image's option set from that file.
#pragma once

// --- Pack (app/pack/pack_view.hpp) ---
// Boards a pack can have in this build: default 64, a full BQ79616 chain. The single-board images
// (BQ769x2, BQ7690x, BQ4050) build with 1: every per-board loop then compiles down to its one board, and a
// view must hold exactly one board. Host builds keep 64, so tests and bms-sim cover the multi-board paths.
#ifndef FW_PACK_MAX_BOARDS
#define FW_PACK_MAX_BOARDS 64
#endif
static_assert(
    FW_PACK_MAX_BOARDS >= 1 && FW_PACK_MAX_BOARDS <= 64,
    "FW_PACK_MAX_BOARDS: 1 (one monitor) up to 64 (the longest BQ79616 chain the CAN ranges cover)");

// --- Protection (app/protection/protection.hpp, app/protection/protection_task.hpp) ---
// Rule::delay (a condition must last that long before it trips or clears). 0 leaves it out: a build without
// it trips on the debounce count alone, so it is only for images whose limits use no delay
// (app/protection/default_limits.hpp: none of the default limits has one).
#ifndef FW_PROTECTION_DELAYS
#define FW_PROTECTION_DELAYS 1
#endif
// Trips logged since start-up with their detection and action times (the log does not wrap: later trips are
// not logged once it is full). 0 leaves the log out (ProtectionTask::log() is then empty); the host keeps 16
// for bms-sim's protection_events.
#ifndef FW_PROTECTION_LOG_SIZE
#define FW_PROTECTION_LOG_SIZE 16
#endif
static_assert(FW_PROTECTION_LOG_SIZE >= 0 && FW_PROTECTION_LOG_SIZE <= 255,
              "FW_PROTECTION_LOG_SIZE: the log's count is one byte");
// ProtectionTask::clearLatched(): a user action (the ClearFaults command) clears latched faults whose
// condition is gone. Default 1 (every image: the command task calls it); 0 clears nothing and a latched fault
// stays until reset.
#ifndef FW_PROTECTION_CLEAR_LATCHED
#define FW_PROTECTION_CLEAR_LATCHED 1
#endif

// --- Commands (app/command) ---
// This BMS's node number: the Target a command must carry (or 255, every BMS) and the Node of its answers
// (firmware/app/can/bms.yaml). 1..254.
#ifndef FW_COMMAND_NODE
#define FW_COMMAND_NODE 1
#endif
static_assert(FW_COMMAND_NODE >= 1 && FW_COMMAND_NODE <= 254,
              "FW_COMMAND_NODE: 1..254 (255 means every BMS)");
// What Identify reports as the image (bms.yaml IdentifyVersion.Image): each image's options.cmake sets its
// number, 1..5; 0 is a host build.
#ifndef FW_IMAGE_ID
#define FW_IMAGE_ID 0
#endif

// --- Publishing (app/publish/publish_status.hpp, app/publish/frame_plan.hpp) ---
// The native messages a build sends: 2, the default (every image, the host and bms-sim), every one; 1,
// PackSummary, ProtectionEvent and CellVoltages (no CellExtremes, Temperatures or TemperatureExtremes); 0,
// PackSummary alone. A level below 2 drops messages: no image ships one (issue 14: every output).
#ifndef FW_PUBLISH_LEVEL
#define FW_PUBLISH_LEVEL 2
#endif
static_assert(FW_PUBLISH_LEVEL >= 0 && FW_PUBLISH_LEVEL <= 2, "FW_PUBLISH_LEVEL: 0, 1 or 2");
// The TI CAN layout (seed 001: TiCellVoltages, big-endian cell codes after each scan): default 1 (host);
// every image except lp-mspm0g3507-bq79616 builds with 0 (their output is the native layout only). Its
// packer also serves the generated pack() of big-endian signals at run time (app/publish/can_bits.hpp).
#ifndef FW_CAN_TI_LAYOUT
#define FW_CAN_TI_LAYOUT 1
#endif

// --- BQ769x2-family application (app/monitors/bq769x_app.hpp) ---
// The start-up CONFIG_UPDATE of the settings table (compared first, written only where the device differs).
// Every image ships with it: without it the BQ76952's ALERT pin stays unconfigured and the BQ76907 ignores
// host FET-off commands (issue 12). Needs the driver's configuration paths (FW_BQ769X_CONFIG_PATHS,
// drivers/bq769x2/config.hpp: checked in app/monitors/bq769x_app.hpp, which sees both).
#ifndef FW_BQ769X_CONFIG_UPDATE
#define FW_BQ769X_CONFIG_UPDATE 1
#endif
// Bq769xAppConfig::faultIndicator, the fault output pin. 0 where the board has none (the L1306).
#ifndef FW_BQ769X_FAULT_INDICATOR
#define FW_BQ769X_FAULT_INDICATOR 1
#endif
// The state of charge (app/soc, Bq769xAppConfig::soc) from the device's accumulated charge, which the driver
// reads every other scan (FW_BQ769X_CHARGE, drivers/bq769x2/config.hpp: needed, checked in
// app/monitors/bq769x_app.hpp). 0: no state of charge in the view (app/soc/soc_view.hpp), so
// PackSummary.StateOfCharge and the StateOfCharge message stay not available: the L1306 images, whose 16 KiB
// it does not fit (README "Open questions"; they set FW_BQ769X_CHARGE=0 too), and the BQ79616 image, which
// has no current input.
#ifndef FW_SOC
#define FW_SOC 1
#endif

// The record store's hooks (app/store/persistence.hpp): the protection task tells an observer of each
// evaluation, the command task runs the store's flash jobs. 0: neither hook is built (the L1306 images,
// whose 16 KiB the store does not fit: README "Open questions").
#ifndef FW_RECORD_STORE
#define FW_RECORD_STORE 1
#endif

// --- Pack storage (app/monitors/storage_mode.hpp) ---
// The pack-storage mode: scans every storage period of the pack file (`storage`), the device's SLEEP where
// it has one and the pack allows it, entry by the StorageMode command or after the pack's rest time, the
// StorageStatus message. 0 leaves it out: StorageMode is answered unsupported and nothing of it is built.
#ifndef FW_STORAGE
#define FW_STORAGE 1
#endif
