# Runs one libFuzzer target for ctest (see CMakeLists.txt).
#   -DTARGET=<fuzz binary> -DNAME=<target name> -DMODE=corpus|fuzz -DCORPUS=<dirs;...> -DWORK=<scratch dir>
#   fuzz mode also: -DSECONDS=<n> -DFINDINGS=<dir for crashing inputs> [-DMAX_LEN=<bytes>]
# corpus: every input of CORPUS once (libFuzzer -runs=0 still executes the whole initial corpus).
# fuzz:   mutates for SECONDS from CORPUS, writing new inputs to WORK/corpus, and prints
#         "REPORT fuzz.<name>.executions=..." (with seconds, rate, coverage edges and new inputs); fails on any
#         crash, leak, timeout or out-of-memory.
set(corpus_dirs "")
foreach(c IN LISTS CORPUS)
  if(IS_DIRECTORY ${c})
    list(APPEND corpus_dirs ${c})
  endif()
endforeach()
# A fresh working corpus each run: a corpus that grew over many runs would take the whole time budget just to
# be loaded (what a run found stays in WORK/corpus until the next run; seeds are what persists).
file(REMOVE_RECURSE ${WORK}/corpus)
file(MAKE_DIRECTORY ${WORK}/corpus)
# -timeout: an input that runs 10 s is a hang (a finding). -rss_limit_mb: as libFuzzer's default, stated.
set(common -timeout=10 -rss_limit_mb=2048 -print_final_stats=1)

if(MODE STREQUAL "corpus")
  execute_process(COMMAND ${TARGET} ${common} -runs=0 ${corpus_dirs} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  string(REGEX MATCH "stat::number_of_executed_units: [0-9]+" runs "${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "fuzz_${NAME}: an input of its corpus fails (exit ${rc}):\n${err}")
  endif()
  message("fuzz_${NAME}: every corpus input passes (${runs})")
  return()
endif()

file(MAKE_DIRECTORY ${FINDINGS})
if(MAX_LEN)
  list(APPEND common -max_len=${MAX_LEN})
endif()
execute_process(COMMAND ${TARGET} ${common} -max_total_time=${SECONDS} -artifact_prefix=${FINDINGS}/
                        ${WORK}/corpus ${corpus_dirs}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCH "stat::number_of_executed_units: *([0-9]+)" _ "${err}")
set(execs "${CMAKE_MATCH_1}")
string(REGEX MATCH "stat::new_units_added: *([0-9]+)" _ "${err}")
set(added "${CMAKE_MATCH_1}")
string(REGEX MATCHALL "cov: [0-9]+" covs "${err}")
list(GET covs -1 cov)
string(REPLACE "cov: " "" cov "${cov}")
if(NOT rc EQUAL 0)
  string(REGEX MATCH "Test unit written to [^\n]+" artifact "${err}")
  string(LENGTH "${err}" len)
  math(EXPR from "${len} - 6000")
  if(from LESS 0)
    set(from 0)
  endif()
  string(SUBSTRING "${err}" ${from} -1 tail)
  message(FATAL_ERROR "fuzz_${NAME} found a failing input (exit ${rc}): ${artifact}\n"
                      "Reproduce: ${TARGET} <that file>. Once fixed, copy it into tests/fuzz/corpus/${NAME}/.\n"
                      "${tail}")
endif()
if(execs STREQUAL "")
  message(FATAL_ERROR "fuzz_${NAME}: no statistics in libFuzzer's output:\n${err}")
endif()
math(EXPR rate "${execs} / ${SECONDS}")
message("REPORT fuzz.${NAME}.executions=${execs} seconds=${SECONDS} per_s=${rate} coverage_edges=${cov} new_inputs=${added}")
