# Runs regmapgen once and compares what it did with golden files (a ctest driver).
#   -DTOOL=<regmapgen> -DARGS=a|b|c     the command line ('|' separates arguments)
#   -DWORKDIR=<dir>                     where to run it (relative paths in goldens stay portable)
#   -DEXPECT_RC=<n>                     required exit status
#   -DEXPECT_STDOUT=<file>              stdout must equal this file        (optional)
#   -DEXPECT_STDERR=<file>              stderr must equal this file        (optional)
#   -DEXPECT_NO_STDERR=ON               stderr must be empty               (optional)
#   -DCHECK_OUTPUT=ON -DSCRATCH=<file>  write stdout to SCRATCH and run `regmapgen check SCRATCH`, which must exit
#                                       with CHECK_RC (default 0) and, if given, print CHECK_STDERR
# With REGMAP_UPDATE_GOLDEN set in the environment the golden files are rewritten instead of compared.
string(REPLACE "|" ";" args "${ARGS}")
if(NOT DEFINED WORKDIR)
  set(WORKDIR ${CMAKE_CURRENT_LIST_DIR})
endif()

function(compare what actual file)
  if(DEFINED ENV{REGMAP_UPDATE_GOLDEN})
    file(WRITE ${file} "${actual}")
    message(STATUS "updated ${file}")
    return()
  endif()
  if(NOT EXISTS ${file})
    message(FATAL_ERROR "missing golden file ${file}; ${what} was:\n${actual}")
  endif()
  file(READ ${file} expected)
  if(NOT actual STREQUAL expected)
    message(FATAL_ERROR "${what} differs from ${file}\n--- expected ---\n${expected}\n--- actual ---\n${actual}\n"
                        "(if the change is intended: REGMAP_UPDATE_GOLDEN=1 ctest -R regmap, then review the diff)")
  endif()
endfunction()

execute_process(COMMAND ${TOOL} ${args} WORKING_DIRECTORY ${WORKDIR}
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "regmapgen ${args}: exit status ${rc}, expected ${EXPECT_RC}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED EXPECT_STDOUT)
  compare("stdout" "${out}" ${EXPECT_STDOUT})
endif()
if(DEFINED EXPECT_STDERR)
  compare("stderr" "${err}" ${EXPECT_STDERR})
endif()
if(EXPECT_NO_STDERR AND NOT err STREQUAL "")
  message(FATAL_ERROR "regmapgen ${args}: expected no diagnostics, got:\n${err}")
endif()

if(CHECK_OUTPUT)
  if(NOT DEFINED CHECK_RC)
    set(CHECK_RC 0)
  endif()
  file(WRITE ${SCRATCH} "${out}")
  execute_process(COMMAND ${TOOL} check ${SCRATCH} WORKING_DIRECTORY ${WORKDIR}
                  OUTPUT_VARIABLE cout ERROR_VARIABLE cerr RESULT_VARIABLE crc)
  if(NOT crc STREQUAL "${CHECK_RC}")
    message(FATAL_ERROR "regmapgen check on the import output: exit ${crc}, expected ${CHECK_RC}\n${cerr}")
  endif()
  if(DEFINED CHECK_STDERR)
    # The scratch file lives in the build tree: compare with its path replaced by a placeholder.
    string(REPLACE "${SCRATCH}" "<import output>" cerr "${cerr}")
    compare("check stderr" "${cerr}" ${CHECK_STDERR})
  endif()
endif()
