# Code and RAM of the BQ769x2 driver for Cortex-M0+ at -Os, as the lp-mspm0l1306-bq76952 image links it.
#
# Compiles firmware/drivers/bq769x2/*.cpp with the firmware flags of bsp/arm-none-eabi.cmake (MinSizeRel),
# plus code_probe.cpp for what lives in the driver's headers (constructors, the BQ76952 variant table), and
# sums the .text/.rodata sections, leaving out the BQ7690x variant tables (separate sections, dropped by
# --gc-sections from a BQ76952 image). ram_probe.cpp sizes the driver object and the measurement record on
# the target (nm prints the size of arrays of exactly those sizes).
# Inputs: CXX, SIZE, NM, SOURCE_DIR, GEN_DIR, WORK_DIR, CODE_BUDGET, RAM_BUDGET.
# Output: "REPORT bq769x2.driver.code_bytes=<n> ram_bytes=<n> record_bytes=<n> (budget ...)".
set(flags -mcpu=cortex-m0plus -mthumb -Os -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti
          -fno-threadsafe-statics -fno-use-cxa-atexit -std=c++20 -Wall -Wextra -Werror
          -I${SOURCE_DIR}/firmware -I${GEN_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(code 0)
# code_probe.cpp instantiates what lives in the driver's headers (constructors, the BQ76952 variant table).
foreach(src link monitor code_probe)
  if(src STREQUAL "code_probe")
    set(path ${CMAKE_CURRENT_LIST_DIR}/code_probe.cpp)
  else()
    set(path ${SOURCE_DIR}/firmware/drivers/bq769x2/${src}.cpp)
  endif()
  execute_process(COMMAND ${CXX} ${flags} -c ${path} -o ${WORK_DIR}/${src}.o
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "compiling ${src}.cpp for Cortex-M0+ failed:\n${err}")
  endif()
  execute_process(COMMAND ${SIZE} -A ${WORK_DIR}/${src}.o OUTPUT_VARIABLE out)
  string(REPLACE "\n" ";" lines "${out}")
  foreach(line IN LISTS lines)
    if(line MATCHES "^\\.(text|rodata|data)[^ ]*[ \t]+([0-9]+)")
      set(n ${CMAKE_MATCH_2})
      if(line MATCHES "kBq7690|kChecks7690x")
        continue()
      endif()
      math(EXPR code "${code} + ${n}")
    endif()
  endforeach()
endforeach()

execute_process(COMMAND ${CXX} ${flags} -c ${CMAKE_CURRENT_LIST_DIR}/ram_probe.cpp -o ${WORK_DIR}/ram_probe.o
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "compiling ram_probe.cpp failed:\n${err}")
endif()
execute_process(COMMAND ${NM} -S ${WORK_DIR}/ram_probe.o OUTPUT_VARIABLE syms)
string(REGEX MATCH "[0-9a-f]+ ([0-9a-f]+) [BbDd] kDriverBytes" m "${syms}")
math(EXPR ram "0x${CMAKE_MATCH_1}")
string(REGEX MATCH "[0-9a-f]+ ([0-9a-f]+) [BbDd] kRecordBytes" m "${syms}")
math(EXPR record "0x${CMAKE_MATCH_1}")

message("REPORT bq769x2.driver.code_bytes=${code} ram_bytes=${ram} record_bytes=${record} (Cortex-M0+ -Os, BQ76952 image; budget ${CODE_BUDGET} / ${RAM_BUDGET})")
if(code GREATER CODE_BUDGET)
  message(FATAL_ERROR "driver code is ${code} B, over its ${CODE_BUDGET} B budget")
endif()
if(ram GREATER RAM_BUDGET)
  message(FATAL_ERROR "driver object is ${ram} B of RAM, over its ${RAM_BUDGET} B budget")
endif()
