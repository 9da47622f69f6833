# lp-mspm0g3507-bq76907: LP-MSPM0G3507 with a BQ76907 (BQ7690x family) on I2C0, CAN out. Not one of the five
# images: the sixth that tests/images/sixth_image_check.cmake adds to a copy of the source tree, to show that
# an image is one folder (and its presets). Variables: bsp/mspm0/images/images.cmake.
set(BMS_IMAGE_CHIP mspm0g3507)
set(BMS_IMAGE_BOARD g3507_can)
set(BMS_IMAGE_FAMILY bq769x2)
set(BMS_IMAGE_DEVICE bq76907)
set(BMS_IMAGE_STACK 2048)
set(BMS_IMAGE_HANDLERS GROUP1_IRQHandler:1 CANFD0_IRQHandler:6 TIMG0_IRQHandler:16 I2C0_IRQHandler:24)
