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
#   BMS_IMAGE_DEFINES       the image's build options (<preset>/options.cmake, one NAME=VALUE a line with its
#                           reason), applied to every firmware library of the image through fw_options so all
#                           translation units agree; the host tests and bms-sim build the image's application
#                           with the same file. Defaults and meanings: the config headers the file names.
# Budgets (the full application on every image: watchdog, start-up configuration, every output, commands,
# balancing, state of charge, record store, bootloader entry): each L1306 image flash 16 384 B (aim 12 KiB) and
# SRAM 3 072 B of the part's 4 KiB including the worst-case stack; each G3507 image flash 24 576 B (aim 16 KiB),
# SRAM 16 KiB (half the part, provisional).
set(BMS_MSPM0_IMAGES_DIR ${CMAKE_CURRENT_LIST_DIR})
set(BMS_MSPM0_IMAGES lp-mspm0l1306-bq76952 lp-mspm0l1306-bq76907 lp-mspm0g3507-bq79616 lp-mspm0g3507-bq4050
                     lp-mspm0g3507-bq76952)

function(bms_image_info image)
  set(l1306_irqs GROUP1_IRQHandler:1 UART0_IRQHandler:15 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  set(g3507_i2c_irqs GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
  if(NOT image IN_LIST BMS_MSPM0_IMAGES)
    message(FATAL_ERROR "unknown MSPM0 image '${image}' (known: ${BMS_MSPM0_IMAGES})")
  endif()
  include(${BMS_MSPM0_IMAGES_DIR}/${image}/options.cmake)
  set(defines ${BMS_IMAGE_OPTIONS})
  if(image STREQUAL "lp-mspm0l1306-bq76952")
    set(row mspm0l1306 l1306_i2c_slcan 1024 16384 3072 "full application" "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0l1306-bq76907")
    set(row mspm0l1306 l1306_i2c_slcan 1024 16384 3072 "full application" "${l1306_irqs}")
  elseif(image STREQUAL "lp-mspm0g3507-bq79616")
    if(BMS_BQ79616_UART STREQUAL "UART1_PA8_PA9")
      set(uart UART1_IRQHandler:13)
    else()
      set(uart UART0_IRQHandler:15)
    endif()
    set(row mspm0g3507 g3507_can 2048 24576 16384 "full application (flash), SRAM provisional"
        "GROUP1_IRQHandler:1;CANFD0_IRQHandler:6;${uart};TIMG0_IRQHandler:16;TIMG6_IRQHandler:17")
  else()  # lp-mspm0g3507-bq4050, lp-mspm0g3507-bq76952
    set(row mspm0g3507 g3507_can 2048 24576 16384 "full application (flash), SRAM provisional" "${g3507_i2c_irqs}")
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

# bms_sources_of(<out> <target>...): the absolute paths of the targets' own sources.
function(bms_sources_of out)
  set(all)
  foreach(target ${ARGN})
    get_target_property(dir ${target} SOURCE_DIR)
    get_target_property(sources ${target} SOURCES)
    foreach(source ${sources})
      cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${dir})
      list(APPEND all ${source})
    endforeach()
  endforeach()
  set(${out} ${all} PARENT_SCOPE)
endfunction()

# bms_image_family(<image> <out>): the image's device family (bq769x2, bq79616, bq4050), the suffix of its
# firmware libraries (fw_app_<family>, fw_drv_<family>), emulator and bms-sim binding.
function(bms_image_family image out)
  if(image MATCHES "-bq769(52|05|07)$")
    set(${out} bq769x2 PARENT_SCOPE)
  elseif(image MATCHES "-bq79616$")
    set(${out} bq79616 PARENT_SCOPE)
  else()
    set(${out} bq4050 PARENT_SCOPE)
  endif()
endfunction()

# bms_image_app_sources(<image> <out>): every target-independent firmware source of the image's application
# (scheduler, application, its device family's app and driver), for builds that compile them with the image's
# options on another target (the QEMU benchmark, the host tests, bms-sim). Call after firmware/ is added.
function(bms_image_app_sources image out)
  bms_image_family(${image} family)
  bms_sources_of(sources fw_sched fw_app fw_app_${family} fw_drv_${family})
  set(${out} ${sources} PARENT_SCOPE)
endfunction()
