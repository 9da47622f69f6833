# Build options of this image: one NAME=VALUE per line, each with its reason. Read by images/images.cmake (the
# image build) and by the host tests and bms-sim, which build this image's application with exactly this set.
# Every option's default, meaning and dependencies: firmware/sched/config.hpp, firmware/core/config.hpp,
# firmware/app/config.hpp, firmware/drivers/bq769x2/config.hpp, bsp/mspm0/config.hpp.
# Options not listed keep their default.
set(BMS_IMAGE_OPTIONS
  FW_IMAGE_ID=4                   # what Identify answers (bms.yaml IdentifyVersion.Image)
  FW_SCHED_MAX_TASKS=4            # protection, monitor, publisher and commands: the only tasks
  FW_SCHED_BUDGETS=0              # saves two clock reads per dispatch: no task has a run-time budget and no output carries the figures
  FW_PACK_MAX_BOARDS=1            # one gauge: a pack of one board
  FW_CAN_TI_LAYOUT=0              # the TI layout (seed 001) is the BQ79616 image's
  BSP_I2C_LISTS=0                 # removes nothing used: the driver starts one transaction at a time
)

# The pack this image builds from unless -DBMS_PACK=<file> names another (firmware/app/packs/README.md): its
# limits, cells and device settings (regmaps/CMakeLists.txt generates it).
set(BMS_IMAGE_PACK bq4050-evm)
