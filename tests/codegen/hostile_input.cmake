# Issue 15 at the command line: each hostile file makes `regmapgen check` or `import` exit 1 with a
# file:line:col error as its first line (not a sanitizer abort, a stack overflow or minutes of work).
#   -DTOOL=<regmapgen> -DDIR=<scratch directory>
file(MAKE_DIRECTORY ${DIR})
string(REPEAT "9" 50000 nines)
string(REPEAT "|" 200000 bars)
string(REPEAT "[" 10000 open)
string(REPEAT "]" 10000 close)
set(entry "family: t\ncommands:\n  - name: A\n    addr: 0x10\n    type: U1\n    access: r\n    description: x\n    source: unverified\n")
set(deep "family: t\nx:\n")
foreach(i RANGE 1 300)
  string(REPEAT " " ${i} indent)
  string(APPEND deep "${indent}a:\n")
endforeach()

function(hostile command name content expected)
  file(WRITE ${DIR}/${name} "${content}")
  execute_process(COMMAND ${TOOL} ${command} ${name} WORKING_DIRECTORY ${DIR} RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  string(FIND "${err}" "\n" eol)
  string(SUBSTRING "${err}" 0 ${eol} first)
  string(FIND "${first}" "${expected}" at)
  if(NOT rc EQUAL 1 OR NOT at EQUAL 0)
    string(SUBSTRING "${err}" 0 600 shown)
    message(FATAL_ERROR "regmapgen ${command} ${name}: exit ${rc}, expected 1 and a first line starting "
                        "'${expected}'; stderr:\n${shown}")
  endif()
  message(STATUS "${command} ${name}: ${first}")
endfunction()

hostile(check no_width.yaml
  "family: t\nfieldsets:\n  - name: Foo\n    description: x\n    source: unverified\n    fields:\n      - name: A\n        bits: 70\n"
  "no_width.yaml:3:5: error: ")
hostile(check long_min.yaml "${entry}    min: 1.${nines}\n" "long_min.yaml:9:4097: error: line is 50011 bytes long")
hostile(check deep_flow.yaml "family: t\nx: ${open}${close}\n" "deep_flow.yaml:2:4097: error: line is 20003 bytes long")
hostile(check deep_map.yaml "${deep}" "deep_map.yaml:2:1: error: unknown key 'x'")
hostile(import long_cell.txt "Address | Name | Type | Units\n0x10 | A | U1 | ${nines} mV\n"
  "long_cell.txt:2:4097: error: line is 50019 bytes long")
hostile(import bars.txt "Address | Name | Type\n${bars}\n" "bars.txt:2:4097: error: line is 200000 bytes long")

# Issue 24: inputs that are not files, or too big to be a map, a table text or a TRM, end at once with a clear
# line (exit 1 for check and import, 2 for diff), whichever command reads them. The 100 MB file is sparse: its
# size is refused before a byte is read.
file(MAKE_DIRECTORY ${DIR}/a_directory)
execute_process(COMMAND truncate -s 100M ${DIR}/big.txt RESULT_VARIABLE truncated)
if(NOT truncated EQUAL 0)
  message(FATAL_ERROR "cannot make a 100 MB sparse file with truncate")
endif()
function(refused command path rc expected)
  if(command STREQUAL "diff")
    set(args diff ${path} ${path})
  else()
    set(args ${command} ${path})
  endif()
  execute_process(COMMAND ${TOOL} ${args} WORKING_DIRECTORY ${DIR} RESULT_VARIABLE got OUTPUT_VARIABLE out
                  ERROR_VARIABLE err TIMEOUT 20)
  string(FIND "${err}" "\n" eol)
  string(SUBSTRING "${err}" 0 ${eol} first)
  if(NOT got EQUAL rc OR NOT first STREQUAL "regmapgen: error: cannot read ${path}: ${expected}")
    message(FATAL_ERROR "regmapgen ${args}: exit ${got}, expected ${rc} and 'regmapgen: error: cannot read "
                        "${path}: ${expected}'; stderr:\n${err}")
  endif()
  message(STATUS "${command} ${path}: ${first}")
endfunction()
foreach(command check import diff)
  if(command STREQUAL "diff")
    set(rc 2)
  else()
    set(rc 1)
  endif()
  refused(${command} /dev/zero ${rc} "is a device, not a file")
  refused(${command} big.txt ${rc} "is 104857600 bytes; inputs are limited to 64 MiB")
endforeach()
# A directory is a set of maps for diff (every *.yaml in it), not a file for check and import.
refused(check a_directory 1 "is a directory")
refused(import a_directory 1 "is a directory")
refused(import /dev/null 1 "is a device, not a file")
# import --map and standard input go through the same limits.
execute_process(COMMAND ${TOOL} import --map /dev/zero ${DIR}/bars.txt RESULT_VARIABLE got ERROR_VARIABLE err
                OUTPUT_QUIET TIMEOUT 20)
if(NOT got EQUAL 1 OR NOT err MATCHES "^regmapgen: error: cannot read map file /dev/zero: is a device, not a file")
  message(FATAL_ERROR "import --map /dev/zero: exit ${got}; stderr:\n${err}")
endif()
execute_process(COMMAND ${TOOL} check - INPUT_FILE /dev/zero RESULT_VARIABLE got ERROR_VARIABLE err OUTPUT_QUIET
                TIMEOUT 60)
if(NOT got EQUAL 1 OR NOT err MATCHES "^regmapgen: error: cannot read standard input: holds more than 67108864 bytes")
  message(FATAL_ERROR "check - < /dev/zero: exit ${got}; stderr:\n${err}")
endif()
message(STATUS "check - < /dev/zero: ${err}")
