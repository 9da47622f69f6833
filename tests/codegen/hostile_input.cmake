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
