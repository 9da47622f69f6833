# The five firmware images: one row each, read by bsp/mspm0/CMakeLists.txt (to build) and by
# tests/firmware/CMakeLists.txt (to check). bms_image_info(<preset>) sets, in the caller's scope:
#   BMS_IMAGE_CHIP          mspm0l1306 | mspm0g3507
#   BMS_IMAGE_SRAM_BASE, BMS_IMAGE_SRAM_SIZE, BMS_IMAGE_FLASH_SIZE   the part's memories (tsv "mem" rows)
#   BMS_IMAGE_BOARD         the board kind in images/common (board_<kind>.cpp)
#   BMS_IMAGE_STACK         stack reservation in bytes (linker --defsym __stack_size__)
#   BMS_IMAGE_FLASH_BUDGET  text + data limit in bytes
#   BMS_IMAGE_SRAM_BUDGET   data + bss + measured worst-case stack limit in bytes
#   BMS_IMAGE_HANDLERS      "<handler>:<irq>" for every peripheral interrupt the image uses
#   BMS_IMAGE_BUDGET_SOURCE where the budgets come from
#   BMS_IMAGE_DEFINES       compile definitions every firmware library of the image is built with (through
#                           fw_options, so all translation units agree): the scheduler's task table size
#                           (FW_SCHED_MAX_TASKS, the image's three tasks) without run-time budgets
#                           (FW_SCHED_BUDGETS=0); no latched-fault clearing without a user action to trigger it
#                           (FW_PROTECTION_CLEAR_LATCHED=0); I2C without transaction lists (BSP_I2C_LISTS=0);
#                           what a single-board image leaves out (FW_PACK_MAX_BOARDS=1, FW_CAN_TI_LAYOUT=0) and
#                           the BQ769x2-family driver built for one family without the CRC-mode probe
#                           (FW_BQ769X_FAMILY, FW_BQ769X_PROBE_CRC=0), the I2C driver without SMBus PEC
#                           (BSP_I2C_PEC=0) and the MCAN driver without reception (BSP_MCAN_RX=0); and on the
#                           8 KiB L1306 what its budget has no room for (bsp/mspm0/README.md, "What the L1306
#                           images leave out"). Host builds use the defaults, so tests and bms-sim cover every
#                           path.
# Budgets: ARCHITECTURE.md gives each L1306 image (flash 10 240 B, SRAM 2 KiB) and lp-mspm0g3507-bq79616
# (flash 12 KiB). The other images take their sibling's budget on the same chip (provisional, set here);
# G3507 images get 16 KiB of SRAM (half the part).
set(BMS_MSPM0_IMAGES lp-mspm0l1306-bq76952 lp-mspm0l1306-bq76907 lp-mspm0g3507-bq79616 lp-mspm0g3507-bq4050
                     lp-mspm0g3507-bq76952)

function(bms_image_info image)
  set(l1306_irqs GROUP1_IRQHandler:1 UART0_IRQHandler:15 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  set(g3507_i2c_irqs GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  # Every image runs three tasks (protection, monitor, publisher: firmware/app/*_app.hpp), none has a user
  # action that clears latched faults yet (firmware/app/protection_task.hpp), and no device driver starts an
  # I2C transaction list longer than one (bsp/mspm0/i2c.hpp), and no task has a run-time budget
  # (firmware/sched/scheduler.hpp).
  set(defines FW_SCHED_MAX_TASKS=3 FW_SCHED_BUDGETS=0 FW_PROTECTION_CLEAR_LATCHED=0 BSP_I2C_LISTS=0)
  if(image MATCHES "^lp-mspm0l1306-")
    # No protection delays (the default limits use none), and no fault output pin on these boards.
    list(APPEND defines FW_PROTECTION_DELAYS=0 FW_BQ769X_FAULT_INDICATOR=0)
    # Dropped to fit the 8 KiB budget (bsp/mspm0/README.md, "What the L1306 images leave out"): the SLCAN
    # messages beyond PackSummary, ProtectionEvent and CellVoltages, the start-up CONFIG_UPDATE, and watchdog
    # supervision.
    list(APPEND defines FW_PUBLISH_LEVEL=0 FW_BQ769X_CONFIG_UPDATE=0 FW_BQ769X_CONFIG_PATHS=0
         FW_WATCHDOG_SUPERVISION=0)
    # Diagnostics nothing in these images reads: the statistics counters and the protection event log.
    list(APPEND defines FW_STATS=0 FW_PROTECTION_LOG_SIZE=0)
  endif()
  # Single-board images compile the multi-board paths down to one board, and only the BQ79616 image (seed
  # 001's TI CAN layout) carries the TI layout (firmware/app/pack_view.hpp, frame_plan.hpp).
  if(NOT image STREQUAL "lp-mspm0g3507-bq79616")
    list(APPEND defines FW_PACK_MAX_BOARDS=1 FW_CAN_TI_LAYOUT=0)
  endif()
  # The BQ769x2-family driver built for the image's one family, without the CRC-mode probe the images'
  # configurations never ask for (firmware/drivers/bq769x2/monitor.hpp).
  # The G3507 applications only transmit on CAN: no MCAN reception (bsp/mspm0/mcan.hpp).
  if(image MATCHES "^lp-mspm0g3507-")
    list(APPEND defines BSP_MCAN_RX=0)
  endif()
  # No SMBus PEC in the I2C driver where nothing uses it (bsp/mspm0/i2c.hpp).
  if(image MATCHES "-bq76952$")
    list(APPEND defines FW_BQ769X_FAMILY=1 FW_BQ769X_PROBE_CRC=0 BSP_I2C_PEC=0)
  elseif(image MATCHES "-bq76907$")
    list(APPEND defines FW_BQ769X_FAMILY=2 FW_BQ769X_PROBE_CRC=0 BSP_I2C_PEC=0)
  endif()
  if(image STREQUAL "lp-mspm0l1306-bq76952")
    set(row mspm0l1306 l1306_i2c_slcan 1024 10240 2048 "ARCHITECTURE.md" "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0l1306-bq76907")
    set(row mspm0l1306 l1306_i2c_slcan 1024 10240 2048 "provisional (sibling lp-mspm0l1306-bq76952)"
        "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0g3507-bq79616")
    if(BMS_BQ79616_UART STREQUAL "UART1_PA8_PA9")
      set(uart UART1_IRQHandler:13)
    else()
      set(uart UART0_IRQHandler:15)
    endif()
    set(row mspm0g3507 g3507_can 2048 12288 16384 "ARCHITECTURE.md (flash), SRAM provisional"
        "GROUP1_IRQHandler:1;CANFD0_IRQHandler:6;${uart};TIMG0_IRQHandler:16;TIMG6_IRQHandler:17")
  elseif(image STREQUAL "lp-mspm0g3507-bq4050")
    set(row mspm0g3507 g3507_can 2048 12288 16384 "provisional (sibling lp-mspm0g3507-bq79616)"
        "${g3507_i2c_irqs}")
  elseif(image STREQUAL "lp-mspm0g3507-bq76952")
    set(row mspm0g3507 g3507_can 2048 12288 16384 "provisional (sibling lp-mspm0g3507-bq79616)"
        "${g3507_i2c_irqs}")
  else()
    message(FATAL_ERROR "unknown MSPM0 image '${image}' (known: ${BMS_MSPM0_IMAGES})")
  endif()
  list(GET row 0 chip)
  list(GET row 1 board)
  list(GET row 2 stack)
  list(GET row 3 flash)
  list(GET row 4 sram)
  list(GET row 5 source)
  list(SUBLIST row 6 -1 handlers)
  set(BMS_IMAGE_CHIP ${chip} PARENT_SCOPE)
  if(chip STREQUAL "mspm0l1306")
    set(BMS_IMAGE_SRAM_BASE 0x20000000 PARENT_SCOPE)
    set(BMS_IMAGE_SRAM_SIZE 0x1000 PARENT_SCOPE)
    set(BMS_IMAGE_FLASH_SIZE 0x10000 PARENT_SCOPE)
  else()
    set(BMS_IMAGE_SRAM_BASE 0x20200000 PARENT_SCOPE)
    set(BMS_IMAGE_SRAM_SIZE 0x8000 PARENT_SCOPE)
    set(BMS_IMAGE_FLASH_SIZE 0x20000 PARENT_SCOPE)
  endif()
  set(BMS_IMAGE_BOARD ${board} PARENT_SCOPE)
  set(BMS_IMAGE_STACK ${stack} PARENT_SCOPE)
  set(BMS_IMAGE_FLASH_BUDGET ${flash} PARENT_SCOPE)
  set(BMS_IMAGE_SRAM_BUDGET ${sram} PARENT_SCOPE)
  set(BMS_IMAGE_BUDGET_SOURCE "${source}" PARENT_SCOPE)
  set(BMS_IMAGE_HANDLERS ${handlers} PARENT_SCOPE)
  set(BMS_IMAGE_DEFINES ${defines} PARENT_SCOPE)
endfunction()
