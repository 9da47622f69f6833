# The BQ4050 gauge application (firmware/app/monitors/bq4050_app.*) with its driver.
target_link_libraries(${BMS_IMAGE} PRIVATE fw_app_bq4050)
