# Fails if any file regmapgen generated into the build (GEN_DIR: gen/regmap/*, gen/can/*) is not as
# clang-format with the repository's .clang-format would write it. The emitters lay their output out
# themselves (codegen/src/emit/lines.hpp); nothing in the build runs clang-format over generated code.
if(NOT CLANG_FORMAT)
  message("SKIP: clang-format not found; generated-code formatting not checked")
  return()
endif()
file(GLOB_RECURSE generated ${GEN_DIR}/regmap/*.hpp ${GEN_DIR}/regmap/*.cpp ${GEN_DIR}/can/*.hpp)
if(NOT generated)
  message(FATAL_ERROR "no generated files under ${GEN_DIR}: build the host preset first")
endif()
execute_process(COMMAND ${CLANG_FORMAT} --style=file:${STYLE} --dry-run --Werror ${generated}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  string(SUBSTRING "${err}" 0 4000 head)  # the first findings are enough to locate the emitter
  message("${head}")
  message(FATAL_ERROR "regmapgen output is not clang-formatted: fix the emitter (codegen/src/emit), "
                      "do not format the output")
endif()
list(LENGTH generated n)
message("clang-format: ${n} generated files clean")
