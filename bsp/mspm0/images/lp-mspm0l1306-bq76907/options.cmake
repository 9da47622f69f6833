# Build options of this image: one NAME=VALUE per line, each with its reason. Read by images/images.cmake (the
# image build) and by the host tests and bms-sim, which build this image's application with exactly this set.
# Every option's default, meaning and dependencies: firmware/sched/config.hpp, firmware/core/config.hpp,
# firmware/app/config.hpp, firmware/drivers/bq769x2/config.hpp, bsp/mspm0/config.hpp.
# Options not listed keep their default.
set(BMS_IMAGE_OPTIONS
  FW_IMAGE_ID=2                   # what Identify answers (bms.yaml IdentifyVersion.Image)
  FW_BQ769X_FAMILY=2              # the BQ7690x family only (BQ76907): the BQ769x2 paths compile away
  FW_SCHED_MAX_TASKS=4            # protection, monitor, publisher and commands: the only tasks
  FW_SCHED_BUDGETS=0              # saves two clock reads per dispatch: no task has a run-time budget and no output carries the figures
  FW_SCHED_POWER_POLICY=0         # saves 40 B: no power policy on this image (STANDBY1 between scans would make it 16 792 B, past its 16 KiB; bsp/mspm0/README.md "Low-power modes")
  FW_PROTECTION_DELAYS=0          # removes nothing: the default limits use no delays (they trip on their debounce count)
  FW_PACK_MAX_BOARDS=1            # one monitor: a pack of one board
  FW_CAN_TI_LAYOUT=0              # SLCAN carries the native messages; the TI layout is the BQ79616 image's
  FW_BQ769X_PROBE_CRC=0           # removes nothing used: the configuration knows the device's CRC mode (probe never asked for)
  FW_BQ769X_CRC=0                 # removes nothing used: the device runs without CRC (link.crc false, the default Comm Type)
  FW_BQ769X_FAULT_INDICATOR=0     # the L1306 board has no fault output pin
  FW_BQ769X_BALANCE=0             # balancing does not fit the 16 KiB budget beside the state of charge (measured 2026-11-29, fourth session: 17 692 B with it; README "The L1306 boards do not hold the full application"); built in, every host and twin test of the image passes
  FW_RECORD_STORE=0               # the record store (app/store) does not fit the 16 KiB (20 916 B with it and balancing, measured 2026-11-29, fourth session; README "The L1306 boards do not hold the full application"): its hooks are built out, nothing kept across a reset; app_init.cpp and data_flash.cpp are ready for 1
  BSP_I2C_LISTS=0                 # removes nothing used: the driver starts one transaction at a time
  FW_STORAGE=0                    # pack storage (StorageMode, StorageStatus) is past the 16 KiB budget for now (firmware/app/monitors/storage_mode.hpp; its cost measured in the storage branch's report): StorageMode is answered unsupported
  FW_BQ769X_SLEEP=0               # nothing asks for SLEEP without storage: startSleep() is left out
  BSP_I2C_PEC=0                   # removes nothing used: the BQ769x2 family has no SMBus PEC
)

# The pack this image builds from unless -DBMS_PACK=<file> names another (firmware/app/packs/README.md): its
# limits, cells and device settings (regmaps/CMakeLists.txt generates it).
set(BMS_IMAGE_PACK bq76907-evm)
