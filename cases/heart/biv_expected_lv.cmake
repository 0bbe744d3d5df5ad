# Acceptance ranges of the biventricular beat's LV (cases/heart/biv_beat.yaml; run_biv.cmake and
# run.sh check cavities.lv against them with check.cmake): the lv heart case's ranges
# (expected.cmake) but two. The wall's volume may change by 1.5 %: the thin RV free wall lets it
# change by 1.3 % at p = 1.5 MPa (1.5 % at p = 1 MPa; at p = 2 MPa the steps were cut to 1/8, a
# projected 10 min). The fibre stretch may fall to 0.55 (0.614 measured, against 0.6 there).
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
set(EXPECT_WALL_VOLUME_CHANGE 0 0.015)
