# lp-mspm0g3507-bq79616: LP-MSPM0G3507 with a BQ79616 daisy chain on UART, nFAULT on PB0, CAN out.
# The image's description, read by images/images.cmake (bms_image_info): everything the build, CI, the
# tests, bms-sim and the twin need to know about it besides its build options (options.cmake) and its
# application (app_init.cpp, board_config.hpp). Variables: images/images.cmake.
set(BMS_IMAGE_CHIP mspm0g3507)
set(BMS_IMAGE_BOARD g3507_can)
set(BMS_IMAGE_FAMILY bq79616)
set(BMS_IMAGE_DEVICE bq79616)
set(BMS_IMAGE_STACK 2048)
# The chain's UART follows the BMS_BQ79616_UART cache option (bsp/mspm0/CMakeLists.txt).
if(BMS_BQ79616_UART STREQUAL "UART1_PA8_PA9")
  set(_uart UART1_IRQHandler:13)
else()
  set(_uart UART0_IRQHandler:15)
endif()
set(BMS_IMAGE_HANDLERS GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 ${_uart} TIMG0_IRQHandler:16 TIMG6_IRQHandler:17)
