# Locking check (issue 23): runs one scene at several volume penalties p (the scene's `p:` value
# of its `volume` term, written `p: <number> kPa`, is replaced) and asserts that the reported value
# changes by at most TOL (relative) from the last (stiffest or augmented) run. A locking element stiffens as p grows,
# so its result keeps moving; a locking-free one converges to the incompressible limit.
#   cmake -DADAMSS=... -DSCENE=... -DOUT=... -DCACHE=... -DPVALUES=500,5000,50000
#         -DVALUE="probes,tip,2" -DTOL=0.003 [-DREF=4.17e-3 -DREF_TOL=0.005] -P check-locking.cmake
# An entry "<p>al" of PVALUES runs at p with `augmented_lagrangian: {tolerance: 1e-6}` added to the
# volume term: the exact-incompressibility option (J = 1 at every constraint to 1e-6), which must
# give the same value. The last entry is the one the others are compared with (list the augmented
# run last). With REF, that value must also lie within REF_TOL (relative) of the reference.
# Every value is printed, pass or fail.
string(REPLACE "," ";" PVALUES "${PVALUES}")
file(READ ${SCENE} text)
get_filename_component(name ${SCENE} NAME_WE)
string(REGEX MATCH "p: [0-9.e+]+ kPa" found "${text}")
if(NOT found)
  message(FATAL_ERROR "${SCENE}: no 'p: <number> kPa' to vary")
endif()
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
string(REPLACE "," ";" keys "${VALUE}")
set(values "")
foreach(p IN LISTS PVALUES)
  if(p MATCHES "^([0-9.e+]+)al$")
    string(REGEX REPLACE "p: [0-9.e+]+ kPa" "p: ${CMAKE_MATCH_1} kPa, augmented_lagrangian: {tolerance: 1e-6}" scene
                         "${text}")
  else()
    string(REGEX REPLACE "p: [0-9.e+]+ kPa" "p: ${p} kPa" scene "${text}")
  endif()
  # Written beside the original so that relative paths in the scene still resolve.
  get_filename_component(dir ${SCENE} DIRECTORY)
  set(variant ${OUT}/${name}-p${p}.yaml)
  file(WRITE ${variant} "${scene}")
  execute_process(COMMAND ${ADAMSS} run ${variant} -o ${OUT}/p${p} --cache ${CACHE} -q RESULT_VARIABLE rc
                  WORKING_DIRECTORY ${dir})
  if(NOT EXISTS ${OUT}/p${p}/summary.json)
    message(FATAL_ERROR "${name} at p = ${p} kPa: exit ${rc}, no summary.json")
  endif()
  file(READ ${OUT}/p${p}/summary.json s)
  string(JSON status GET "${s}" status)
  string(JSON v GET "${s}" ${keys})
  string(JSON dv GET "${s}" total_volume_m3 max_abs_relative_change)
  string(JSON al ERROR_VARIABLE no_al GET "${s}" augmented_lagrangian max_volume_ratio_violation)
  if(no_al)
    set(al "-")
  endif()
  message(STATUS "${name}: p = ${p} kPa: ${VALUE} = ${v}, max |dV/V| = ${dv}, "
                 "augmented max |J - 1| ${al}, status ${status}")
  if(NOT status STREQUAL "completed")
    message(FATAL_ERROR "${name} at p = ${p} kPa: status ${status}")
  endif()
  if(p MATCHES "al$")
    set(loose 1)
    if(NOT al STREQUAL "-")
      execute_process(COMMAND awk "BEGIN{exit (${al}+0 <= 1e-6) ? 0 : 1}" RESULT_VARIABLE loose)
    endif()
    if(loose)
      message(FATAL_ERROR "${name} at p = ${p} kPa: the augmented Lagrangian left max |J - 1| = ${al} (> 1e-6)")
    endif()
  endif()
  list(APPEND values ${v})
endforeach()
list(GET values -1 ref)
set(failures "")
foreach(v IN LISTS values)
  execute_process(COMMAND awk "BEGIN{d=(${v})-(${ref}); if (d<0) d=-d; r=(${ref}); if (r<0) r=-r; exit (d <= ${TOL}*r) ? 0 : 1}"
                  RESULT_VARIABLE bad)
  if(bad)
    set(failures "${failures}\n  ${v} differs from the last run's ${ref} by more than ${TOL} (relative)")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "${name} locks:${failures}")
endif()
if(DEFINED REF AND NOT REF STREQUAL "")
  execute_process(COMMAND awk "BEGIN{d=(${ref})-(${REF}); if (d<0) d=-d; r=(${REF}); if (r<0) r=-r; exit (d <= ${REF_TOL}*r) ? 0 : 1}"
                  RESULT_VARIABLE off)
  if(off)
    message(FATAL_ERROR "${name}: ${VALUE} = ${ref} is not within ${REF_TOL} (relative) of the reference ${REF}")
  endif()
  message(STATUS "${name}: ${VALUE} = ${ref} within ${REF_TOL} (relative) of the reference ${REF}")
endif()
message(STATUS "${name}: ${VALUE} within ${TOL} (relative) over p = ${PVALUES} kPa")
