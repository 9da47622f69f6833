# `regmapgen list` per family must show at least the issue's acceptance counts (BQ769x2 subcommands: the 77 of
# SLUUBY2B Tables 12-22 and 12-23; BQ4050 data flash: the 538 rows of SLUUAQ3A Table 14-1).
#   -DTOOL=<regmapgen> -DMAPS=<regmaps dir>
set(expect
  "bq769x2:command:55" "bq769x2:subcommand:77" "bq769x2:datamem:270"
  "bq7690x:command:30" "bq7690x:subcommand:19" "bq7690x:datamem:70"
  "bq79616:register:300"
  "bq4050:sbs:55" "bq4050:mac:50" "bq4050:dataflash:538")
set(failed "")
foreach(item IN LISTS expect)
  string(REPLACE ":" ";" parts "${item}")
  list(GET parts 0 family)
  list(GET parts 1 kind)
  list(GET parts 2 minimum)
  file(GLOB files ${MAPS}/${family}/*.yaml)
  execute_process(COMMAND ${TOOL} list ${files} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "regmapgen list ${family} failed:\n${err}")
  endif()
  string(REGEX MATCHALL "(^|\n)${kind} 0x[0-9A-F]+ [A-Za-z_][A-Za-z0-9_]* [^\n]+" lines "${out}")
  list(LENGTH lines n)
  message(STATUS "${family}: ${n} ${kind} entries (need >= ${minimum})")
  if(n LESS minimum)
    string(APPEND failed "${family}: ${n} ${kind} entries, need at least ${minimum}\n")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "${failed}")
endif()
