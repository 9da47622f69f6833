# Keeps the generated blocks of regmaps/README.md in step with regmapgen.
#   cmake -DREGMAPGEN=<exe> -DREADME=<file> -DMODE=check|update -P readme_blocks.cmake
# A block is the text between "<!-- BEGIN regmapgen NAME -->" and "<!-- END regmapgen NAME -->"; NAME is a
# regmapgen command whose stdout is the block (schema, glossary). check fails on any difference; update
# rewrites the file.
foreach(var REGMAPGEN README MODE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "readme_blocks.cmake needs -D${var}=...")
  endif()
endforeach()

file(READ ${README} text)
set(new "${text}")
foreach(block schema glossary)
  execute_process(COMMAND ${REGMAPGEN} ${block} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "regmapgen ${block} failed (${rc})")
  endif()
  set(begin "<!-- BEGIN regmapgen ${block} -->")
  set(end "<!-- END regmapgen ${block} -->")
  string(FIND "${new}" "${begin}" b)
  string(FIND "${new}" "${end}" e)
  if(b EQUAL -1 OR e EQUAL -1 OR e LESS b)
    message(FATAL_ERROR "${README}: missing '${begin}' ... '${end}'")
  endif()
  string(LENGTH "${begin}" blen)
  math(EXPR start "${b} + ${blen}")
  string(SUBSTRING "${new}" 0 ${start} head)
  string(SUBSTRING "${new}" ${e} -1 tail)
  set(new "${head}\n${out}${tail}")
endforeach()

if(MODE STREQUAL "update")
  if(NOT new STREQUAL text)
    file(WRITE ${README} "${new}")
    message(STATUS "updated ${README}")
  endif()
elseif(NOT new STREQUAL text)
  message(FATAL_ERROR "${README} is stale: its generated blocks differ from `regmapgen schema` / `regmapgen glossary`.\n"
                      "Run: cmake --build --preset host --target update-regmap-docs")
else()
  message(STATUS "${README}: generated blocks are current")
endif()
