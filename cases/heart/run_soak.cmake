# cmake -DADAMSS=... -DSCENE=cases/heart/lv_soak.yaml -DOUT=... -DCACHE=... -P run_soak.cmake
# The soak test (ctest case.heart.soak): 50 beats of the quick heart scene, then
#  - memory flat: resident memory at the end at most 2 MB above its value at t_end / 4
#    (summary.json resident_memory_MB; 37 beats = 3 700 steps in between, so a leak of 600 bytes
#    per step fails);
#  - the loop periodic: EDV, ESV and peak pressure of beats 10 to 50 within 1 % of each other
#    (range / mean; measured 0.14 %, 0.41 %, 0.36 %), beat 50 within 0.5 % of beat 49;
#  - the run completed with 50 beats.
set(EXPECT_BEATS 50)
set(MAX_GROWTH_MB 2)
set(MAX_SPREAD 0.01)
set(MAX_LAST_CHANGE 0.005)

# The run and its "completed" check are tests/run_case.cmake's (it leaves the summary in `summary`).
include(${CMAKE_CURRENT_LIST_DIR}/../../tests/run_case.cmake)
set(s "${summary}")

set(failures "")
# awk_true(out "expression"): out = 1 when the awk expression holds.
function(awk_true out expr)
  execute_process(COMMAND awk "BEGIN{exit (${expr}) ? 0 : 1}" RESULT_VARIABLE bad)
  if(bad)
    set(${out} 0 PARENT_SCOPE)
  else()
    set(${out} 1 PARENT_SCOPE)
  endif()
endfunction()

string(JSON beats GET "${s}" cavities lv beats)
awk_true(ok "${beats} == ${EXPECT_BEATS}")
if(NOT ok)
  set(failures "${failures}\n  beats = ${beats}, expected ${EXPECT_BEATS}")
endif()

string(JSON quarter GET "${s}" resident_memory_MB at_quarter_of_t_end)
string(JSON final GET "${s}" resident_memory_MB final)
string(JSON peak GET "${s}" resident_memory_MB peak)
awk_true(ok "${final} - ${quarter} <= ${MAX_GROWTH_MB}")
if(ok)
  message(STATUS "  resident memory: ${quarter} MB at t_end/4, ${final} MB at the end (peak ${peak}): ok")
else()
  set(failures "${failures}\n  resident memory grew from ${quarter} MB (t_end/4) to ${final} MB (end), over ${MAX_GROWTH_MB} MB")
endif()

string(JSON n LENGTH "${s}" cavities lv per_beat)
if(n LESS 50)
  message(FATAL_ERROR "soak: ${n} beats in cavities.lv.per_beat, expected 50")
endif()
math(EXPR last "${n} - 1")
math(EXPR before_last "${n} - 2")
foreach(key edv_m3 esv_m3 peak_pressure_Pa)
  set(values "")
  foreach(i RANGE 9 ${last})
    string(JSON v GET "${s}" cavities lv per_beat ${i} ${key})
    list(APPEND values ${v})
  endforeach()
  list(JOIN values " " vs)
  execute_process(COMMAND awk "BEGIN{n=split(\"${vs}\", a, \" \"); lo=a[1]; hi=a[1]; m=0;
      for (i = 1; i <= n; i++) { if (a[i] < lo) lo = a[i]; if (a[i] > hi) hi = a[i]; m += a[i] / n }
      printf \"%.6g %.6g\", (hi - lo) / m, (a[n] - a[n-1]) / a[n-1] }"
    OUTPUT_VARIABLE r)
  separate_arguments(r)
  list(GET r 0 spread)
  list(GET r 1 change)
  awk_true(ok1 "${spread} <= ${MAX_SPREAD}")
  # Parenthesised: a negative change would otherwise read "--2.9e-05", an awk syntax error.
  awk_true(ok2 "((${change}) < 0 ? -(${change}) : (${change})) <= ${MAX_LAST_CHANGE}")
  if(ok1 AND ok2)
    message(STATUS "  ${key}: beats 10-50 spread ${spread}, beat 50 vs 49 ${change}: ok")
  else()
    set(failures "${failures}\n  ${key}: beats 10-50 spread ${spread} (max ${MAX_SPREAD}), beat 50 vs 49 ${change} (max ${MAX_LAST_CHANGE})")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "soak test failed:${failures}")
endif()
