# cmake -DFUZZER=... -DSEEDS=corpus/NAME -DWORK=dir -DSECONDS=60 -P run_fuzzer.cmake
# Copies the seed corpus to WORK/corpus, runs the fuzzer for SECONDS with bounded memory and time
# per input, prints libFuzzer's final statistics (executions, coverage) and fails on any finding.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/corpus ${WORK}/artifacts)
file(GLOB seeds ${SEEDS}/*)
file(COPY ${seeds} DESTINATION ${WORK}/corpus)
execute_process(COMMAND ${FUZZER} ${WORK}/corpus -max_total_time=${SECONDS} -timeout=20 -rss_limit_mb=3072
                        -max_len=65536 -print_final_stats=1 -artifact_prefix=${WORK}/artifacts/
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCHALL "stat::[a-z_]+: *[0-9]+" stats "${err}")
message(STATUS "${FUZZER}: ${stats}")
if(NOT rc EQUAL 0)
  string(LENGTH "${err}" n)
  if(n GREATER 6000)
    math(EXPR start "${n} - 6000")
    string(SUBSTRING "${err}" ${start} 6000 err)
  endif()
  message(FATAL_ERROR "${FUZZER} found a problem (exit ${rc}); reproducer in ${WORK}/artifacts/\n${err}")
endif()
