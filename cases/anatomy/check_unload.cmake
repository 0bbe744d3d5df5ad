# cmake -DADAMSS=... -DSCENE=NAME.yaml -DEXPECTED=NAME.unload.cmake -DOUT=... -DCACHE=... -P check_unload.cmake
# Runs `adamss unload SCENE` with the expected file's tolerance and iteration limit (counting
# iteration 0, the loading of the image itself), then checks
# OUT/unload.json: converged; every cavity of the best iteration re-filled within
# EXPECT_RELOADED_WITHIN (relative) of the image's volume; each EXPECT_UNLOADED entry's unloaded
# volume within its margin. Every value is printed.
include(${EXPECTED})
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ADAMSS} unload ${SCENE} -o ${OUT} --cache ${CACHE} --tolerance ${UNLOAD_TOLERANCE}
                        --max-iterations ${UNLOAD_MAX_ITERATIONS} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "adamss unload ${SCENE} exited with ${rc} (${OUT}/unload.json says why)")
endif()
file(READ ${OUT}/unload.json u)
string(JSON best GET "${u}" best_iteration)
string(JSON n LENGTH "${u}" iterations)
string(JSON err GET "${u}" max_error_m)
message(STATUS "converged after ${n} iterations, max distance ${err} m")
set(failures "")
include(${CMAKE_CURRENT_LIST_DIR}/../within.cmake)
string(JSON ncav LENGTH "${u}" imaged_cavity_volumes_m3)
math(EXPR last "${ncav} - 1")
foreach(i RANGE ${last})
  string(JSON name MEMBER "${u}" imaged_cavity_volumes_m3 ${i})
  string(JSON image GET "${u}" imaged_cavity_volumes_m3 ${name})
  string(JSON loaded GET "${u}" iterations ${best} cavities ${name} loaded_m3)
  within("${name} re-filled volume (m^3) against the image's" ${loaded} ${image} ${EXPECT_RELOADED_WITHIN})
endforeach()
foreach(entry ${EXPECT_UNLOADED})
  string(REPLACE "|" ";" f "${entry}")
  list(GET f 0 name)
  list(GET f 1 expected)
  list(GET f 2 margin)
  string(JSON ref GET "${u}" iterations ${best} cavities ${name} reference_m3)
  within("${name} unloaded volume (m^3)" ${ref} ${expected} ${margin})
endforeach()
if(failures)
  message(FATAL_ERROR "unloading off its expected values:${failures}")
endif()
