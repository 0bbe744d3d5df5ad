# cmake -DHEALTHY=OUT/summary.json -DSCARRED=OUT/scar/summary.json -DEXPECTED=cases/heart/expected.cmake -P check_scar.cmake
# The planning scenario: the scarred beat completes, its ejection fraction lies in
# EXPECT_SCAR_EJECTION_FRACTION and is lower than the healthy one by at least EXPECT_SCAR_EF_DROP_MIN.
include(${EXPECTED})
if(NOT DEFINED CAVITY)
  set(CAVITY lv)  # summary.json cavities.NAME
endif()
file(READ ${HEALTHY} h)
file(READ ${SCARRED} s)
string(JSON status GET "${s}" status)
if(NOT status STREQUAL EXPECT_STATUS)
  message(FATAL_ERROR "heart case (scar): status ${status}, expected ${EXPECT_STATUS}")
endif()
string(JSON ef_h ERROR_VARIABLE err GET "${h}" cavities ${CAVITY} ejection_fraction)
if(err)
  message(FATAL_ERROR "heart case: ${HEALTHY} has no ejection_fraction (${err})")
endif()
string(JSON ef_s ERROR_VARIABLE err GET "${s}" cavities ${CAVITY} ejection_fraction)
if(err)
  message(FATAL_ERROR "heart case (scar): ${SCARRED} has no ejection_fraction (the beat did not complete?)")
endif()
list(GET EXPECT_SCAR_EJECTION_FRACTION 0 lo)
list(GET EXPECT_SCAR_EJECTION_FRACTION 1 hi)
execute_process(COMMAND awk "BEGIN{exit (${ef_s} >= ${lo} && ${ef_s} <= ${hi} && ${ef_h} - ${ef_s} >= ${EXPECT_SCAR_EF_DROP_MIN}) ? 0 : 1}"
                RESULT_VARIABLE bad)
if(bad)
  message(FATAL_ERROR "heart case (scar): EF healthy ${ef_h}, scarred ${ef_s}: expected the scarred EF in [${lo}, ${hi}] "
                      "and at least ${EXPECT_SCAR_EF_DROP_MIN} below the healthy one")
endif()
message(STATUS "  ejection fraction healthy ${ef_h}, scarred ${ef_s} (lower by >= ${EXPECT_SCAR_EF_DROP_MIN}): ok")
