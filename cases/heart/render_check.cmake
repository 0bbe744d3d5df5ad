# ctest case.heart.render and case.anatomy.render.bivme-beat: runs cases/heart/render_heart.py on a
# finished heart run, then checks that the picture was written and the long-axis numbers of its JSON.
#   cmake -DPYTHON=python3 -DSCRIPT=render_heart.py -DSIM=<run folder> -DPNG=<picture>
#         -DEXPECT_LENGTH_ED_MM="lo hi" -DEXPECT_CHANGE="lo hi" -P render_check.cmake
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${SIM} ${PNG} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_heart.py failed (${rc})")
endif()
file(SIZE ${PNG} png_bytes)
if(png_bytes LESS 20000)
  message(FATAL_ERROR "${PNG} has ${png_bytes} bytes: not a picture of the mesh")
endif()
string(REGEX REPLACE "\\.png$" ".json" json ${PNG})
file(READ ${json} s)

# key of the JSON, its scale to the band's unit, the band "lo hi" (CMake compares no decimals: Python does)
function(check_band key scale band)
  separate_arguments(band UNIX_COMMAND "${band}")
  list(GET band 0 lo)
  list(GET band 1 hi)
  string(JSON v GET "${s}" ${key})
  execute_process(COMMAND ${PYTHON} -c "import sys; sys.exit(0 if ${lo} <= ${v} * ${scale} <= ${hi} else 1)"
                  RESULT_VARIABLE outside)
  if(NOT outside EQUAL 0)
    message(FATAL_ERROR "${key} = ${v} (x ${scale}) is outside [${lo}, ${hi}]")
  endif()
  message(STATUS "${key} = ${v} (x ${scale}) in [${lo}, ${hi}]")
endfunction()
check_band(long_axis_length_ed_m 1000 "${EXPECT_LENGTH_ED_MM}")
check_band(long_axis_change 1 "${EXPECT_CHANGE}")
