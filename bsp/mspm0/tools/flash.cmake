# `cmake --build <dir> --target flash`: programs the image into a LaunchPad, with the first way that applies:
#   0. bmsctl flash through the MSPM0 ROM bootloader on the LaunchPad's USB serial port, when BMS_FLASH_PORT
#      names it (-DBMS_FLASH_PORT=/dev/ttyACM0 at configure time, or the environment variable). It needs the
#      host tools (build/host/bin/bmsctl, or bmsctl on PATH). BMS_FLASH_BAUD (environment; default 115200) is
#      the line rate after the connection, BMS_FLASH_INVOKE (button | app | none; default button) how the
#      bootloader is started: bsp/mspm0/README.md "Flashing".
#   1. OpenOCD with MSPM0 support (mainline after 0.12.0, or TI's fork): it must find an MSPM0 target config.
#      Debian bookworm's openocd 0.12.0 has none and is skipped with a note.
#   2. TI UniFlash's command line, dslite.sh, with a target configuration (.ccxml) given in the environment
#      variable BMS_UNIFLASH_CCXML (UniFlash: choose the LaunchPad, then "Standalone Command Line" export).
# Otherwise it stops and names what to install. Inputs: ELF, HEX, CHIP (mspm0l1306 | mspm0g3507), PORT, BMSCTL.
if(NOT PORT AND DEFINED ENV{BMS_FLASH_PORT})
  set(PORT $ENV{BMS_FLASH_PORT})
endif()
if(PORT)
  if(NOT EXISTS "${BMSCTL}")
    find_program(BMSCTL_ON_PATH bmsctl)
    set(BMSCTL ${BMSCTL_ON_PATH})
  endif()
  if(NOT BMSCTL)
    message(FATAL_ERROR "flash: BMS_FLASH_PORT is ${PORT} but bmsctl is not built: "
                        "cmake --preset host && cmake --build --preset host --target bmsctl")
  endif()
  set(baud 115200)
  if(DEFINED ENV{BMS_FLASH_BAUD})
    set(baud $ENV{BMS_FLASH_BAUD})
  endif()
  set(invoke button)
  if(DEFINED ENV{BMS_FLASH_INVOKE})
    set(invoke $ENV{BMS_FLASH_INVOKE})
  endif()
  message(STATUS "flash: ${BMSCTL} flash ${ELF} --port ${PORT} --chip ${CHIP} --baud ${baud} --invoke ${invoke}")
  execute_process(COMMAND ${BMSCTL} flash ${ELF} --port ${PORT} --chip ${CHIP} --baud ${baud} --invoke ${invoke}
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "flash: bmsctl flash failed (exit ${rc}, its message above)")
  endif()
  return()
endif()

set(board_configs board/ti/mspm0-launchpad.cfg board/ti_mspm0_launchpad.cfg)
set(target_configs target/ti/mspm0.cfg target/ti_mspm0.cfg)

find_program(OPENOCD openocd)
if(OPENOCD)
  foreach(cfg IN LISTS board_configs target_configs)
    execute_process(COMMAND ${OPENOCD} -c "puts \[find ${cfg}\]" -c shutdown RESULT_VARIABLE rc OUTPUT_QUIET
                    ERROR_QUIET)
    if(rc EQUAL 0)
      if(cfg IN_LIST board_configs)
        set(args -f ${cfg})
      else()
        set(args -f interface/xds110.cfg -f ${cfg})
      endif()
      message(STATUS "flash: ${OPENOCD} ${args} (${CHIP})")
      execute_process(COMMAND ${OPENOCD} ${args} -c "program ${ELF} verify reset exit" RESULT_VARIABLE rc)
      if(NOT rc EQUAL 0)
        message(FATAL_ERROR "flash: OpenOCD failed (${rc}); is the LaunchPad connected by USB?")
      endif()
      return()
    endif()
  endforeach()
  message(STATUS "flash: ${OPENOCD} has no MSPM0 target config (Debian's 0.12.0 does not); trying UniFlash")
endif()

find_program(DSLITE NAMES dslite.sh dslite PATHS $ENV{HOME}/ti/uniflash/deskdb/content/TICloudAgent/linux/ccs_base/DebugServer/bin
             /opt/ti/uniflash)
if(DSLITE AND DEFINED ENV{BMS_UNIFLASH_CCXML})
  message(STATUS "flash: ${DSLITE} with $ENV{BMS_UNIFLASH_CCXML} (${CHIP})")
  execute_process(COMMAND ${DSLITE} --config=$ENV{BMS_UNIFLASH_CCXML} -f -v ${ELF} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "flash: dslite failed (${rc})")
  endif()
  return()
endif()

message(FATAL_ERROR
  "flash: no programmer for ${CHIP} found. Either give the LaunchPad's serial port to use its ROM bootloader\n"
  "(BMS_FLASH_PORT=/dev/ttyACM0, or -DBMS_FLASH_PORT=..., with the host tools built), or install one of:\n"
  "  - OpenOCD built from the current openocd.org sources (MSPM0 support: target/ti/mspm0.cfg), then rerun;\n"
  "  - TI UniFlash (https://www.ti.com/tool/UNIFLASH), export a standalone command line package for the\n"
  "    LaunchPad and set BMS_UNIFLASH_CCXML=<path to its .ccxml>, with dslite.sh on PATH.\n"
  "The image to program is ${HEX} (or ${ELF}).")
