# Build options of this image: one NAME=VALUE per line, each with its reason. Read by images/images.cmake (the
# image build) and by the host tests and bms-sim, which build this image's application with exactly this set.
# Every option's default, meaning and dependencies: firmware/sched/config.hpp, firmware/core/config.hpp,
# firmware/app/config.hpp, firmware/drivers/bq769x2/config.hpp, bsp/mspm0/config.hpp.
# Options not listed keep their default.
set(BMS_IMAGE_OPTIONS
  FW_IMAGE_ID=1                   # what Identify answers (bms.yaml IdentifyVersion.Image)
  FW_BQ769X_FAMILY=1              # the BQ769x2 family only (BQ76952): the BQ7690x paths compile away
  FW_SCHED_MAX_TASKS=4            # protection, monitor, publisher and commands: the only tasks
  FW_SCHED_BUDGETS=0              # saves two clock reads per dispatch: no task has a run-time budget and no output carries the figures
  FW_PROTECTION_DELAYS=0          # removes nothing: the default limits use no delays (they trip on their debounce count)
  FW_PACK_MAX_BOARDS=1            # one monitor: a pack of one board
  FW_CAN_TI_LAYOUT=0              # SLCAN carries the native messages; the TI layout is the BQ79616 image's
  FW_BQ769X_PROBE_CRC=0           # removes nothing used: the configuration knows the device's CRC mode (probe never asked for)
  FW_BQ769X_CRC=0                 # removes nothing used: the device runs without CRC (link.crc false, the default Comm Type)
  FW_BQ769X_FAULT_INDICATOR=0     # the L1306 board has no fault output pin
  FW_BQ769X_BALANCE=0             # balancing does not fit the 16 KiB budget (measured 2026-11-29, fourth session: 18 772 B with SOC and the accumulated charge; README "The L1306 boards do not hold the full application"); built in, every host and twin test of the image passes
  FW_SOC=0                        # the state of charge is past the 16 KiB budget (measured 2026-11-29, fourth session: 17 344 B with it and the accumulated charge, 960 B past; README "The L1306 boards do not hold the full application"): PackSummary.StateOfCharge and the StateOfCharge message stay not available
  FW_BQ769X_CHARGE=0              # nothing counts the accumulated charge without the state of charge: the scan leaves its request and read out
  FW_RECORD_STORE=0               # the record store (app/store) does not fit the 16 KiB (22 032 B with it, balancing and SOC, measured 2026-11-29, fourth session; README "The L1306 boards do not hold the full application"): its hooks are built out, nothing kept across a reset; app_init.cpp and data_flash.cpp are ready for 1
  BSP_I2C_LISTS=0                 # removes nothing used: the driver starts one transaction at a time
  BSP_DEEP_IDLE=1                 # STANDBY1 between scans (bsp/mspm0/power_policy.hpp): the MCU's average current, computed on the twin, from 993 to 92 uA; 572 B of flash (bsp/mspm0/README.md "Low-power modes")
  FW_STORAGE=0                    # pack storage (StorageMode, StorageStatus) is past the 16 KiB budget for now (firmware/app/monitors/storage_mode.hpp; its cost measured in the storage branch's report): StorageMode is answered unsupported
  FW_BQ769X_SLEEP=0               # nothing asks for SLEEP without storage: startSleep() is left out
  BSP_I2C_PEC=0                   # removes nothing used: the BQ769x2 family has no SMBus PEC
)

# The pack this image builds from unless -DBMS_PACK=<file> names another (firmware/app/packs/README.md): its
# limits, cells and device settings (regmaps/CMakeLists.txt generates it).
set(BMS_IMAGE_PACK bq76952-evm)
