# cmake -DADAMSS=... -DSCENE=bivme-beat.yaml -DUNLOAD=DIR -DOUT=... -DCACHE=... -P run_bivme_beat.cmake
# The biv-me beat from the unloaded reference that case.anatomy.unload.bivme-filling left in DIR
# (DIR/unloaded_mesh.h5, DIR/unload.json): the end-diastolic volumes must be the meshed image's within
# 1 % (cases/heart/check_unloaded_edv.cmake) and both cavities' summaries within
# bivme-beat_expected_lv.cmake / _rv.cmake (cases/heart/check.cmake).
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} run ${SCENE} -o ${OUT} --cache ${CACHE} --reference ${UNLOAD}/unloaded_mesh.h5 -q
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss run ${SCENE} exited with ${rc} (${OUT}/run.log says why)")
endif()
set(SUMMARY ${OUT}/summary.json)
set(UNLOAD ${UNLOAD}/unload.json)
include(${CMAKE_CURRENT_LIST_DIR}/../heart/check_unloaded_edv.cmake)
foreach(CAVITY lv rv)
  message(STATUS "cavity ${CAVITY}:")
  set(EXPECTED ${CMAKE_CURRENT_LIST_DIR}/bivme-beat_expected_${CAVITY}.cmake)
  include(${CMAKE_CURRENT_LIST_DIR}/../heart/check.cmake)
endforeach()
