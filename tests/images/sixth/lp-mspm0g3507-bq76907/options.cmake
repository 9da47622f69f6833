# Build options of this image: one NAME=VALUE per line, each with its reason (bsp/mspm0/images/*/options.cmake).
set(BMS_IMAGE_OPTIONS
  FW_IMAGE_ID=6                   # what Identify answers (not named in bms.yaml's IdentifyVersion.Image)
  FW_BQ769X_FAMILY=2              # the BQ7690x family only (BQ76907): the BQ769x2 paths compile away
  FW_SCHED_MAX_TASKS=4            # protection, monitor, publisher and commands: the only tasks
  FW_SCHED_BUDGETS=0              # no task has a run-time budget and no output carries the figures
  FW_PACK_MAX_BOARDS=1            # one monitor: a pack of one board
  FW_CAN_TI_LAYOUT=0              # the TI layout (seed 001) is the BQ79616 image's
  FW_BQ769X_PROBE_CRC=0           # the configuration knows the device's CRC mode
  FW_BQ769X_CRC=0                 # the device runs without CRC (the default Comm Type)
  BSP_I2C_LISTS=0                 # the driver starts one transaction at a time
  BSP_I2C_PEC=0                   # the BQ769x2 family has no SMBus PEC
)

# The pack this image builds from unless -DBMS_PACK=<file> names another (firmware/app/packs/README.md).
set(BMS_IMAGE_PACK bq76907-evm)
