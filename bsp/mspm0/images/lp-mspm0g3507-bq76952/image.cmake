# lp-mspm0g3507-bq76952: LP-MSPM0G3507 with a BQ76952 (BQ769x2 family) on I2C0, CAN out.
# The image's description, read by images/images.cmake (bms_image_info): everything the build, CI, the
# tests, bms-sim and the twin need to know about it besides its build options (options.cmake) and its
# application (app_init.cpp, board_config.hpp). Variables: images/images.cmake.
set(BMS_IMAGE_CHIP mspm0g3507)
set(BMS_IMAGE_BOARD g3507_can)
set(BMS_IMAGE_FAMILY bq769x2)
set(BMS_IMAGE_DEVICE bq76952)
set(BMS_IMAGE_STACK 2048)
set(BMS_IMAGE_HANDLERS GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
