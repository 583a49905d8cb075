# cmake -DFUZZER=... -DCORPUS=dir -DDICT=file -DWORK=dir -DLIMIT=-runs=N|-max_total_time=S -P run_fuzzer.cmake
# Runs one libFuzzer harness from a scratch copy of the committed corpus, in WORK: the inputs
# it adds and any crash-/leak-/timeout- file it writes stay there. A crash, a leak, undefined
# behaviour, an input slower than 10 s or a process above 2 GiB fails the test.
foreach(v FUZZER CORPUS WORK LIMIT)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_fuzzer.cmake: -D${v}=... is required")
  endif()
endforeach()
if(NOT EXISTS ${FUZZER})
  message(FATAL_ERROR "${FUZZER} is not built (the target axg_fuzzers builds it)")
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/corpus ${WORK}/artifacts)
file(GLOB seeds ${CORPUS}/*)
file(COPY ${seeds} DESTINATION ${WORK}/corpus)
set(dict)
if(DEFINED DICT AND EXISTS ${DICT})
  set(dict -dict=${DICT})
endif()
execute_process(
  COMMAND ${FUZZER} ${LIMIT} -rss_limit_mb=2048 -timeout=10 -max_len=16384 -print_final_stats=1
          -artifact_prefix=${WORK}/artifacts/ ${dict} ${WORK}/corpus
  WORKING_DIRECTORY ${WORK}
  RESULT_VARIABLE rc
  ERROR_VARIABLE log
  OUTPUT_VARIABLE out)
file(WRITE ${WORK}/fuzz.log "${out}${log}")
# The summary libFuzzer ends with: "Done N runs in S second(s)" and the stat:: lines.
string(REGEX MATCHALL "(#[0-9]+[ \t]+DONE[^\n]*|Done [0-9]+ runs[^\n]*|stat::[^\n]*)" summary "${log}")
foreach(line ${summary})
  message(STATUS "${line}")
endforeach()
file(GLOB artifacts ${WORK}/artifacts/*)
if(NOT rc EQUAL 0 OR artifacts)
  string(LENGTH "${log}" n)
  if(n GREATER 6000)
    math(EXPR start "${n} - 6000")
    string(SUBSTRING "${log}" ${start} 6000 log)
  endif()
  message(FATAL_ERROR "${FUZZER} failed (exit ${rc}); inputs in ${WORK}/artifacts, log ${WORK}/fuzz.log\n${log}")
endif()
