# Acceptance ranges of the biventricular beat's RV (cases/heart/biv_beat.yaml): the LV's
# (biv_expected_lv.cmake: the loop, beat, fibre-stretch and wall-volume checks, the last two being
# the whole heart's keys) but for human RV pressures: peak systolic 3-5 kPa (20-40 mmHg, the
# range issue 20 asks of the biv-me heart) and the right atrial filling pressure, 0.5 kPa given.
include(${CMAKE_CURRENT_LIST_DIR}/biv_expected_lv.cmake)
set(EXPECT_PEAK_PRESSURE_PA 3000 5000)
set(EXPECT_EDP_PA 200 1000)
