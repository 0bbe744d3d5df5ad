# cmake -DADAMSS=... -DSCENE=... -DOUT=... -DCACHE=... -P run_biv.cmake
# The biventricular beat as make heart runs it (run.sh step 4c): `adamss unload` on
# cases/heart/biv_unload.yaml (the phantom taken as the end-diastolic image) into OUT/unload, then
# the beat (cases/heart/biv_beat.yaml, SCENE) from that unloaded reference (--reference). Checks that
# the unloading converged and the beat's end-diastolic volumes are the image's within 1 %
# (check_unloaded_edv.cmake), and both cavities' summaries with check.cmake: cavities.lv against
# biv_expected_lv.cmake, cavities.rv against biv_expected_rv.cmake.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} unload ${CMAKE_CURRENT_LIST_DIR}/biv_unload.yaml -o ${OUT}/unload --cache ${CACHE}
                        --tolerance 0.05mm --max-iterations 12 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss unload biv_unload.yaml exited with ${rc}")
endif()
execute_process(COMMAND ${ADAMSS} run ${SCENE} -o ${OUT} --cache ${CACHE} --reference ${OUT}/unload/unloaded_mesh.h5 -q
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss run ${SCENE} exited with ${rc}")
endif()
set(SUMMARY ${OUT}/summary.json)
set(UNLOAD ${OUT}/unload/unload.json)
include(${CMAKE_CURRENT_LIST_DIR}/check_unloaded_edv.cmake)
foreach(CAVITY lv rv)
  message(STATUS "cavity ${CAVITY}:")
  set(EXPECTED ${CMAKE_CURRENT_LIST_DIR}/biv_expected_${CAVITY}.cmake)
  include(${CMAKE_CURRENT_LIST_DIR}/check.cmake)
endforeach()
