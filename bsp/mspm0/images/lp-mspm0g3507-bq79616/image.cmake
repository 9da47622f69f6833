# The BQ79616 chain application (firmware/app/monitors/bq79616_app.*) with its driver.
target_link_libraries(${BMS_IMAGE} PRIVATE fw_app_bq79616)
