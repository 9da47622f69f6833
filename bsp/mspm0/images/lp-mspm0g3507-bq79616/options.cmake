# Build options of this image: one NAME=VALUE per line, each with its reason. Read by images/images.cmake (the
# image build) and by the host tests and bms-sim, which build this image's application with exactly this set.
# Every option's default, meaning and dependencies: firmware/sched/config.hpp, firmware/core/config.hpp,
# firmware/app/config.hpp, firmware/drivers/bq769x2/config.hpp, bsp/mspm0/config.hpp.
# Options not listed keep their default.
set(BMS_IMAGE_OPTIONS
  FW_IMAGE_ID=3                   # what Identify answers (bms.yaml IdentifyVersion.Image)
  BMS_BOARD_MONITOR_ON_UART=1     # the monitor is a BQ79616 chain on a UART, not a device on I2C0
  FW_SCHED_MAX_TASKS=4            # protection, monitor, publisher and commands: the only tasks
  FW_SCHED_BUDGETS=0              # saves two clock reads per dispatch: no task has a run-time budget and no output carries the figures
  BSP_I2C_LISTS=0                 # removes nothing used: the board's I2C is not built
  FW_SOC=0                        # no current input, so no state of charge: the view keeps none, StateOfCharge goes out not available
  FW_STORAGE=0                    # its monitor has no storage mode yet (firmware/app/monitors/storage_mode.hpp: the BQ769x-family one only): StorageMode is answered unsupported, and the view, StorageStatus and the answer cost nothing
)

# The pack this image builds from unless -DBMS_PACK=<file> names another (firmware/app/packs/README.md): its
# limits, cells and device settings (regmaps/CMakeLists.txt generates it).
set(BMS_IMAGE_PACK bq79616-evm)
