# Issue 26: the register map agrees with TI's TRM except for the documented deviations.
#   -DTOOL=<regmapgen> -DFAMILY=<family> -DMAPS=<regmaps dir> -DREADME=<regmaps/README.md>
#   "-DPAGES=<ti/a.txt|ti/b.txt...>" (excerpts of one TRM, joined in this order) -DEXPECTED=<ti/<doc>.deviations>
#   -DSCRATCH=<file>
# Runs `regmapgen import --family FAMILY <joined excerpts> --against MAPS/FAMILY` and requires its output to
# be exactly the lines of EXPECTED (each a deviation the README's deviations log explains), and every entry
# those lines name to appear in the README. A new difference, or a deviation that went away, fails.
string(REPLACE "|" ";" pages "${PAGES}")
file(WRITE ${SCRATCH} "")
foreach(p IN LISTS pages)
  file(READ ${p} text)
  file(APPEND ${SCRATCH} "${text}")
endforeach()
execute_process(COMMAND ${TOOL} import --family ${FAMILY} ${SCRATCH} --against ${MAPS}/${FAMILY}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
file(READ ${EXPECTED} expected)
if(NOT out STREQUAL expected)
  file(WRITE ${SCRATCH}.out "${out}")
  execute_process(COMMAND diff -u ${EXPECTED} ${SCRATCH}.out OUTPUT_VARIABLE shown)
  message(FATAL_ERROR "regmapgen import --against ${MAPS}/${FAMILY}: the differences are not the documented "
                      "deviations (exit ${rc}; - documented, + found):\n${shown}\nstderr:\n${err}")
endif()
if(expected STREQUAL "" AND NOT rc EQUAL 0 OR NOT expected STREQUAL "" AND NOT rc EQUAL 1)
  message(FATAL_ERROR "exit ${rc}, expected 0 (no difference) or 1 (the deviations)\n${err}")
endif()
# Each deviation's entry is named in the README's deviations log.
file(READ ${README} readme)
string(REPLACE "\n" ";" lines "${expected}")
foreach(l IN LISTS lines)
  if(l STREQUAL "")
    continue()
  endif()
  string(REGEX MATCH "'([^']+)'" _ "${l}")
  string(FIND "${readme}" "${CMAKE_MATCH_1}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "deviation '${l}': '${CMAKE_MATCH_1}' is not named in ${README}")
  endif()
endforeach()
string(REGEX MATCH "regmapgen: [0-9]+ added, [0-9]+ removed, [0-9]+ changed, [0-9]+ unchanged" counts "${err}")
message(STATUS "${FAMILY}: ${counts}")
