# cmake -DADAMSS=... -DSCENE=... -DOUT=... -DCACHE=... -P run_biv.cmake
# Runs the biventricular beat (cases/heart/biv_beat.yaml) and checks both cavities' summaries with
# check.cmake: cavities.lv against biv_expected_lv.cmake, cavities.rv against biv_expected_rv.cmake.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} run ${SCENE} -o ${OUT} --cache ${CACHE} -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss run ${SCENE} exited with ${rc}")
endif()
set(SUMMARY ${OUT}/summary.json)
foreach(CAVITY lv rv)
  message(STATUS "cavity ${CAVITY}:")
  set(EXPECTED ${CMAKE_CURRENT_LIST_DIR}/biv_expected_${CAVITY}.cmake)
  include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)
endforeach()
