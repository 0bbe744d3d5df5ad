# cmake -DRUN_IMAGE=cases/heart/run_image.sh -DADAMSS=... -DIMAGE=... -DOUT=... "-DEF=min max" [-DESV_REQUIRED=ON]
#       -P run_image_check.cmake
# The whole `make heart HEART_IMAGE=IMAGE` pipeline (cases/heart/run_image.sh: mesh, unloading, two
# beats, report) and its image_comparison.json: the run completed, the LV ejection fraction of the
# last beat lies in EF (a band around the value measured when the test was written, so that a
# change is seen), and, where the image has an end-systolic blood pool (required with ESV_REQUIRED),
# the simulated ESV is within 15 % of it (issue 20; run_image.sh fails on that too).
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${RUN_IMAGE} ${ADAMSS} ${IMAGE} ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run_image.sh ${IMAGE} exited with ${rc} (its log above; results in ${OUT})")
endif()
file(READ ${OUT}/image_comparison.json json)
string(JSON status GET "${json}" status)
if(NOT status STREQUAL "completed")
  message(FATAL_ERROR "image_comparison.json: status '${status}', expected 'completed'")
endif()
string(JSON ef GET "${json}" lv ejection_fraction)
separate_arguments(EF)  # "min max" from the command line
list(GET EF 0 ef_min)
list(GET EF 1 ef_max)
if(ef LESS ef_min OR ef GREATER ef_max)
  message(FATAL_ERROR "LV ejection fraction ${ef}, expected in [${ef_min}, ${ef_max}]")
endif()
message(STATUS "LV ejection fraction ${ef} (expected in [${ef_min}, ${ef_max}]): ok")
string(JSON esv_error ERROR_VARIABLE no_es GET "${json}" lv esv_error_vs_image)
if(no_es AND ESV_REQUIRED)
  message(FATAL_ERROR "image_comparison.json has no lv.esv_error_vs_image (the end-systolic blood pool was not read)")
endif()
if(NOT no_es)
  if(esv_error LESS -0.15 OR esv_error GREATER 0.15)
    message(FATAL_ERROR "ESV ${esv_error} off the image's end-systolic blood pool, expected within 0.15")
  endif()
  message(STATUS "ESV against the image's end-systolic blood pool ${esv_error} (within 0.15): ok")
endif()
