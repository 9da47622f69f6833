# Fails if any C++ source in the repository is not formatted as .clang-format says.
file(GLOB_RECURSE sources
  ${SOURCE_DIR}/firmware/*.cpp ${SOURCE_DIR}/firmware/*.hpp
  ${SOURCE_DIR}/bsp/*.cpp ${SOURCE_DIR}/bsp/*.hpp
  ${SOURCE_DIR}/codegen/*.cpp ${SOURCE_DIR}/codegen/*.hpp
  ${SOURCE_DIR}/tests/*.cpp ${SOURCE_DIR}/tests/*.hpp)
list(FILTER sources EXCLUDE REGEX "/build/")
execute_process(COMMAND ${CLANG_FORMAT} --dry-run --Werror ${sources} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message("${err}")
  message(FATAL_ERROR "some files are not clang-formatted; run: clang-format -i <files>")
endif()
list(LENGTH sources n)
message("clang-format: ${n} files clean")
