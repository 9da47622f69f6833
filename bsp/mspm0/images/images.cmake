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
# Budgets: ARCHITECTURE.md gives lp-mspm0l1306-bq76952 (flash 8 240 B, SRAM 2 KiB) and lp-mspm0g3507-bq79616
# (flash 12 KiB). The other images take their sibling's budget on the same chip (provisional, set here);
# G3507 images get 16 KiB of SRAM (half the part).
set(BMS_MSPM0_IMAGES lp-mspm0l1306-bq76952 lp-mspm0l1306-bq76907 lp-mspm0g3507-bq79616 lp-mspm0g3507-bq4050
                     lp-mspm0g3507-bq76952)

function(bms_image_info image)
  set(l1306_irqs GROUP1_IRQHandler:1 UART0_IRQHandler:15 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  set(g3507_i2c_irqs GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  if(image STREQUAL "lp-mspm0l1306-bq76952")
    set(row mspm0l1306 l1306_i2c_slcan 1024 8240 2048 "ARCHITECTURE.md" "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0l1306-bq76907")
    set(row mspm0l1306 l1306_i2c_slcan 1024 8240 2048 "provisional (sibling lp-mspm0l1306-bq76952)"
        "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0g3507-bq79616")
    if(BMS_BQ79616_UART STREQUAL "UART1_PA8_PA9")
      set(uart UART1_IRQHandler:13)
    else()
      set(uart UART0_IRQHandler:15)
    endif()
    set(row mspm0g3507 g3507_uart_can 2048 12288 16384 "ARCHITECTURE.md (flash), SRAM provisional"
        "GROUP1_IRQHandler:1;CANFD0_IRQHandler:6;${uart};TIMG0_IRQHandler:16;TIMG6_IRQHandler:17")
  elseif(image STREQUAL "lp-mspm0g3507-bq4050")
    set(row mspm0g3507 g3507_i2c_can 2048 12288 16384 "provisional (sibling lp-mspm0g3507-bq79616)"
        "${g3507_i2c_irqs}")
  elseif(image STREQUAL "lp-mspm0g3507-bq76952")
    set(row mspm0g3507 g3507_i2c_can 2048 12288 16384 "provisional (sibling lp-mspm0g3507-bq79616)"
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
endfunction()
