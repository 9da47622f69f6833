# The BQ769x2-family application (firmware/app/monitors/bq769x_app.*) with the BQ769x2 driver.
target_link_libraries(${BMS_IMAGE} PRIVATE fw_app_bq769x2)
