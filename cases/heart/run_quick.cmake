# cmake -DADAMSS=... -DSCENE=... -DOUT=... -DCACHE=... -DEXPECTED=... [-DHEALTHY=SUMMARY] -P run_quick.cmake
# Runs a quick heart scene and checks its summary: with check.cmake, or with HEALTHY (the healthy
# quick run's summary.json) against it with check_scar.cmake (the scarred EF must be lower).
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} run ${SCENE} -o ${OUT} --cache ${CACHE} -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss run ${SCENE} exited with ${rc}")
endif()
if(DEFINED HEALTHY)
  set(SCARRED ${OUT}/summary.json)
  include(${CMAKE_CURRENT_LIST_DIR}/check_scar.cmake)
else()
  set(SUMMARY ${OUT}/summary.json)
  include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)
endif()
