# lp-mspm0l1306-bq76907: LP-MSPM0L1306 with a BQ76907 (BQ7690x, driven by the BQ769x2-family driver) on I2C0, SLCAN on the back-channel UART.
# The image's description, read by images/images.cmake (bms_image_info): everything the build, CI, the
# tests, bms-sim and the twin need to know about it besides its build options (options.cmake) and its
# application (app_init.cpp, board_config.hpp). Variables: images/images.cmake.
set(BMS_IMAGE_CHIP mspm0l1306)
set(BMS_IMAGE_BOARD l1306_i2c_slcan)
set(BMS_IMAGE_FAMILY bq769x2)
set(BMS_IMAGE_DEVICE bq76907)
set(BMS_IMAGE_STACK 1024)
set(BMS_IMAGE_HANDLERS GROUP1_IRQHandler:1 UART0_IRQHandler:15 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
