# Reads one adamss summary.json and prints one tab-separated line:
#   status reason solver_wall_s steps elements nodes qoi qoi2
# qoi for land-p1: tip z (m); land-p2: endocardial apex z (m); cube: bottom reaction force z (N),
# qoi2 (cube only): relative volume change. Missing values print as "null".
#   cmake -DSUMMARY=OUT/summary.json -DPROBLEM=p1|p2|p3 -P extract.cmake
file(READ "${SUMMARY}" s)
macro(get var)
  string(JSON ${var} ERROR_VARIABLE err GET "${s}" ${ARGN})
  if(err OR "${${var}}" STREQUAL "" OR "${${var}}" MATCHES "NOTFOUND")
    set(${var} null)
  endif()
endmacro()
get(status status)
get(reason reason)
get(wall wall_time_s)
get(steps steps)
get(elements elements)
get(nodes nodes)
set(qoi2 null)
if(PROBLEM STREQUAL "p1")
  get(qoi probes tip 2)
elseif(PROBLEM STREQUAL "p2")
  get(qoi probes endo_apex 2)
else()
  get(qoi reactions 0 reaction_force_N 2)
  get(qoi2 total_volume_m3 relative_change)
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E echo
  "${status}\t${reason}\t${wall}\t${steps}\t${elements}\t${nodes}\t${qoi}\t${qoi2}")
