# cmake -DADAMSS=... -DSCENE=... -DOUT=... -DCACHE=... -DEXPECTED=... -P run_quick.cmake
# Runs the quick heart beat and checks its summary with check.cmake.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} run ${SCENE} -o ${OUT} --cache ${CACHE} -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss run ${SCENE} exited with ${rc}")
endif()
set(SUMMARY ${OUT}/summary.json)
include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)
