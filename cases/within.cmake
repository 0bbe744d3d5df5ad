# within(what value expected margin): passes when |value / expected - 1| <= margin (relative), and
# prints the value either way; a miss is appended to the caller's `failures`. CMake has no
# floating-point arithmetic: awk compares (the values go in by -v, so signs cannot form "--").
# Included by cases/heart/check_unloaded_edv.cmake and cases/anatomy/check_unload.cmake.
function(within what value expected margin)
  execute_process(COMMAND awk -v v=${value} -v x=${expected} -v m=${margin}
                          "BEGIN{d = v / x - 1; printf \"%+.3f\", 100 * d; exit (d <= m && d >= -m) ? 0 : 1}"
                  OUTPUT_VARIABLE pct RESULT_VARIABLE bad)
  if(bad)
    set(failures "${failures}\n  ${what} = ${value}, expected ${expected} within ${margin} (${pct} %)" PARENT_SCOPE)
  else()
    message(STATUS "  ${what} = ${value} (${pct} % of ${expected}, margin ${margin}): ok")
  endif()
endfunction()
