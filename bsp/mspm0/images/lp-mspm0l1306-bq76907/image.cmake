# This image's application does not fit its 8 240 B budget yet (see bsp/mspm0/README.md), so it runs the
# heartbeat, which needs the LaunchPad LED.
target_compile_definitions(${BMS_IMAGE} PRIVATE BMS_BOARD_LED_BUTTON=1)
