# The firmware images: one folder each under this one, found by its image.cmake (the image's description).
# Read by bsp/mspm0/CMakeLists.txt (to build), by tests/ (to check and to run on the host and the twin), by
# bms-sim's build and, through `bms_image_names` in ci/test's way of listing folders, by CI. Adding an image
# is adding a folder (bsp/mspm0/README.md, "Adding an image"); CMakePresets.json must name it too, which the
# test `images.presets` checks.
#
# bms_image_info(<preset>) sets, in the caller's scope:
#   BMS_IMAGE_CHIP          mspm0l1306 | mspm0g3507                                  (image.cmake)
#   BMS_IMAGE_BOARD         the board kind in images/common (board_<kind>.cpp)         (image.cmake)
#   BMS_IMAGE_FAMILY        bq769x2 | bq79616 | bq4050: the suffix of its firmware libraries (fw_app_<family>,
#                           fw_drv_<family>), emulator and bms-sim binding                  (image.cmake)
#   BMS_IMAGE_DEVICE        the monitor part (bq76952, bq76907, bq79616, bq4050), the preset's suffix
#                                                                                            (image.cmake)
#   BMS_IMAGE_STACK         stack reservation in bytes (linker --defsym __stack_size__)    (image.cmake)
#   BMS_IMAGE_HANDLERS      "<handler>:<irq>" for every peripheral interrupt the image uses (image.cmake)
#   BMS_IMAGE_SRAM_BASE, BMS_IMAGE_SRAM_SIZE, BMS_IMAGE_FLASH_SIZE   the part's memories (tsv "mem" rows)
#   BMS_IMAGE_FLASH_BUDGET  text + data limit in bytes                                     (the chip's)
#   BMS_IMAGE_SRAM_BUDGET   data + bss + measured worst-case stack limit in bytes          (the chip's)
#   BMS_IMAGE_BUDGET_SOURCE where the budgets come from
#   BMS_IMAGE_DEFINES       the image's build options (<preset>/options.cmake, one NAME=VALUE a line with its
#                           reason), applied to every firmware library of the image through fw_options so all
#                           translation units agree; the host tests and bms-sim build the image's application
#                           with the same file. Defaults and meanings: the config headers the file names.
# Budgets (the full application on every image: watchdog, start-up configuration, every output, commands,
# balancing, state of charge, record store, bootloader entry), per chip: each L1306 image flash 16 384 B (aim
# 12 KiB) and SRAM 3 072 B of the part's 4 KiB including the worst-case stack; each G3507 image flash
# 24 576 B (aim 16 KiB), SRAM 16 KiB (half the part, provisional).
set(BMS_MSPM0_IMAGES_DIR ${CMAKE_CURRENT_LIST_DIR})
file(GLOB _descriptions RELATIVE ${BMS_MSPM0_IMAGES_DIR} ${BMS_MSPM0_IMAGES_DIR}/*/image.cmake)
set(BMS_MSPM0_IMAGES)
foreach(_description ${_descriptions})
  get_filename_component(_image ${_description} DIRECTORY)
  list(APPEND BMS_MSPM0_IMAGES ${_image})
endforeach()
list(SORT BMS_MSPM0_IMAGES)

function(bms_image_info image)
  if(NOT image IN_LIST BMS_MSPM0_IMAGES)
    message(FATAL_ERROR "unknown MSPM0 image '${image}' (known: ${BMS_MSPM0_IMAGES})")
  endif()
  foreach(var CHIP BOARD FAMILY DEVICE STACK HANDLERS)
    unset(BMS_IMAGE_${var})
  endforeach()
  include(${BMS_MSPM0_IMAGES_DIR}/${image}/image.cmake)
  foreach(var CHIP BOARD FAMILY DEVICE STACK HANDLERS)
    if("${BMS_IMAGE_${var}}" STREQUAL "")
      message(FATAL_ERROR "${BMS_MSPM0_IMAGES_DIR}/${image}/image.cmake: BMS_IMAGE_${var} is not set")
    endif()
  endforeach()
  # The preset's name states the board's part and the monitor (lp-<chip>-<device>): tools and the twin read it.
  if(NOT image STREQUAL "lp-${BMS_IMAGE_CHIP}-${BMS_IMAGE_DEVICE}")
    message(FATAL_ERROR "${image}/image.cmake: an image is named lp-<chip>-<device> "
                        "(here lp-${BMS_IMAGE_CHIP}-${BMS_IMAGE_DEVICE})")
  endif()
  include(${BMS_MSPM0_IMAGES_DIR}/${image}/options.cmake)
  if(BMS_IMAGE_CHIP STREQUAL "mspm0l1306")
    set(memories 0x20000000 0x1000 0x10000)
    set(budgets 16384 3072 "full application")
  elseif(BMS_IMAGE_CHIP STREQUAL "mspm0g3507")
    set(memories 0x20200000 0x8000 0x20000)
    set(budgets 24576 16384 "full application (flash), SRAM provisional")
  else()
    message(FATAL_ERROR "${image}/image.cmake: unknown chip '${BMS_IMAGE_CHIP}' (mspm0l1306, mspm0g3507)")
  endif()
  foreach(var CHIP BOARD FAMILY DEVICE STACK HANDLERS)
    set(BMS_IMAGE_${var} ${BMS_IMAGE_${var}} PARENT_SCOPE)
  endforeach()
  list(GET memories 0 base)
  list(GET memories 1 sram)
  list(GET memories 2 flash)
  set(BMS_IMAGE_SRAM_BASE ${base} PARENT_SCOPE)
  set(BMS_IMAGE_SRAM_SIZE ${sram} PARENT_SCOPE)
  set(BMS_IMAGE_FLASH_SIZE ${flash} PARENT_SCOPE)
  list(GET budgets 0 flash_budget)
  list(GET budgets 1 sram_budget)
  list(GET budgets 2 source)
  set(BMS_IMAGE_FLASH_BUDGET ${flash_budget} PARENT_SCOPE)
  set(BMS_IMAGE_SRAM_BUDGET ${sram_budget} PARENT_SCOPE)
  set(BMS_IMAGE_BUDGET_SOURCE "${source}" PARENT_SCOPE)
  set(BMS_IMAGE_DEFINES ${BMS_IMAGE_OPTIONS} PARENT_SCOPE)
endfunction()

# bms_images(<out> [CHIP <chip>] [BOARD <kind>] [FAMILY <family>]): the images, or those on one chip, board
# kind or device family.
function(bms_images out)
  cmake_parse_arguments(arg "" "CHIP;BOARD;FAMILY" "" ${ARGN})
  set(selected)
  foreach(image ${BMS_MSPM0_IMAGES})
    bms_image_info(${image})
    if(arg_CHIP AND NOT BMS_IMAGE_CHIP STREQUAL arg_CHIP)
      continue()
    endif()
    if(arg_BOARD AND NOT BMS_IMAGE_BOARD STREQUAL arg_BOARD)
      continue()
    endif()
    if(arg_FAMILY AND NOT BMS_IMAGE_FAMILY STREQUAL arg_FAMILY)
      continue()
    endif()
    list(APPEND selected ${image})
  endforeach()
  set(${out} ${selected} PARENT_SCOPE)
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

# bms_image_family(<image> <out>): the image's device family (bq769x2, bq79616, bq4050), from its description.
function(bms_image_family image out)
  bms_image_info(${image})
  set(${out} ${BMS_IMAGE_FAMILY} PARENT_SCOPE)
endfunction()

# bms_image_app_sources(<image> <out>): every target-independent firmware source of the image's application
# (scheduler, application, its device family's app and driver), for builds that compile them with the image's
# options on another target (the QEMU benchmark, the host tests, bms-sim). Call after firmware/ is added.
function(bms_image_app_sources image out)
  bms_image_family(${image} family)
  bms_sources_of(sources fw_sched fw_app fw_app_${family} fw_drv_${family})
  set(${out} ${sources} PARENT_SCOPE)
endfunction()
