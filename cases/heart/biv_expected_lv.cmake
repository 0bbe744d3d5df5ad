# Acceptance ranges of the biventricular beat's LV (cases/heart/biv_beat.yaml; run_biv.cmake and
# run.sh check cavities.lv against them with check.cmake): the lv heart case's ranges
# (expected.cmake) but one: the fibre stretch may fall to 0.55 (0.618 measured, against 0.6 there).
# The wall's volume changes by 0.97 % at most (uncoupled law, p = 2 MPa; it was 1.30 % with the
# coupled law at p = 1.5 MPa), within the 1 % of issue 23 like the lv case.
set(EXPECT_STATUS completed)
set(EXPECT_EJECTION_FRACTION 0.40 0.70)
set(EXPECT_PEAK_PRESSURE_PA 12000 18000)
set(EXPECT_EDP_PA 500 2000)
set(EXPECT_ISOVOLUMIC_DRIFT 0 0.005)
set(EXPECT_LOOP_CLOSURE 0 0.02)
set(EXPECT_BEATS 2)
set(EXPECT_BEAT_TO_BEAT_CHANGE 0 0.02)
set(EXPECT_FIBER_STRETCH_MIN 0.55 1.0)
set(EXPECT_FIBER_STRETCH_MAX 1.0 1.5)
set(EXPECT_WALL_VOLUME_CHANGE 0 0.01)
