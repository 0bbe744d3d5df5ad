# cmake -DUNLOAD=OUT/unload/unload.json -DSUMMARY=OUT/biv/summary.json [-DTOLERANCE=0.01] -P check_unloaded_edv.cmake
# A beat started from the unloaded reference of `adamss unload` must fill back to the image: for
# every cavity of unload.json's imaged_cavity_volumes_m3, the beat's end-diastolic volume
# (summary.json cavities.NAME.edv_m3) within TOLERANCE (relative, default 1 %; issue 20 asks 3 %) of
# the image's. Fails too when the unloading did not converge.
if(NOT DEFINED TOLERANCE)
  set(TOLERANCE 0.01)
endif()
file(READ ${UNLOAD} u)
file(READ ${SUMMARY} s)
string(JSON converged GET "${u}" converged)
if(NOT converged)
  string(JSON stop GET "${u}" stop)
  message(FATAL_ERROR "unloading did not converge: ${stop}")
endif()
string(JSON n LENGTH "${u}" imaged_cavity_volumes_m3)
if(n EQUAL 0)
  message(FATAL_ERROR "${UNLOAD} lists no cavity volumes")
endif()
math(EXPR last "${n} - 1")
set(failures "")
foreach(i RANGE ${last})
  string(JSON name MEMBER "${u}" imaged_cavity_volumes_m3 ${i})
  string(JSON image GET "${u}" imaged_cavity_volumes_m3 ${name})
  string(JSON edv GET "${s}" cavities ${name} edv_m3)
  execute_process(COMMAND awk -v e=${edv} -v i=${image} -v t=${TOLERANCE}
                          "BEGIN{d = (e - i) / i; printf \"%+.3f\", 100 * d; exit (d <= t && d >= -t) ? 0 : 1}"
                  OUTPUT_VARIABLE pct RESULT_VARIABLE bad)
  if(bad)
    set(failures "${failures}\n  ${name}: EDV ${edv} m^3 against the image's ${image} m^3 (${pct} %)")
  else()
    message(STATUS "  ${name}: EDV ${edv} m^3, image ${image} m^3 (${pct} %, within ${TOLERANCE}): ok")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "end-diastolic volumes off the image:${failures}")
endif()
