# Toolchain for Cortex-M0+ (MSPM0L1306 / MSPM0G3507) and the ARMv6-M QEMU target.
# Debian's gcc-arm-none-eabi 12 with newlib-nano. C++ is compiled with arm-none-eabi-g++ but linked with
# arm-none-eabi-gcc: the C++ runtime libraries are not needed (ci/setup installs only libstdc++'s headers), and
# any accidental use of them (operator new, __cxa_*, unwinding) becomes a link error instead of kilobytes of silent bloat.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "objcopy")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "size")

set(BMS_CPU_FLAGS "-mcpu=cortex-m0plus -mthumb")
set(CMAKE_C_FLAGS_INIT "${BMS_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${BMS_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit")
set(CMAKE_ASM_FLAGS_INIT "${BMS_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${BMS_CPU_FLAGS} --specs=nano.specs --specs=nosys.specs -nostartfiles -Wl,--gc-sections")

# -fno-move-loop-invariants: on ARMv6-M's eight low registers the constants GCC hoists out of loops cost
# spills and reloads; measured -40..-56 B per image (README figures), same code for the images and qemu-m0.
# -fno-inline-functions-called-once -fno-partial-inlining: under link-time optimisation GCC otherwise folds
# every function with one caller (a task's steps, the start-up wiring) into its caller, and on those eight
# registers the merged bodies spill more than the calls they save cost; measured on the balancing L1306
# images -300 B (BQ76952) and -224 B (BQ7690x), every image smaller (README figures).
# Written into the cache on every configure (FORCE): an *_INIT value is read only when a build directory is
# first configured, so a build directory made before a change here kept building with the old flags (an
# L1306 image measured 260 B larger, over its budget, in a directory configured before the two options above).
set(BMS_SIZE_FLAGS "-Os -fno-move-loop-invariants -fno-inline-functions-called-once -fno-partial-inlining -g")
set(CMAKE_C_FLAGS_MINSIZEREL "${BMS_SIZE_FLAGS} -DNDEBUG" CACHE STRING "MinSizeRel flags (bsp/arm-none-eabi.cmake)" FORCE)
set(CMAKE_CXX_FLAGS_MINSIZEREL "${BMS_SIZE_FLAGS} -DNDEBUG" CACHE STRING "MinSizeRel flags (bsp/arm-none-eabi.cmake)" FORCE)

# Link C++ executables through the C driver (see above).
set(CMAKE_CXX_LINK_EXECUTABLE
    "<CMAKE_C_COMPILER> <FLAGS> <CMAKE_CXX_LINK_FLAGS> <LINK_FLAGS> <OBJECTS> -o <TARGET> <LINK_LIBRARIES>")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
