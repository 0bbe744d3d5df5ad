# Regression bands of the biv-me beat's RV (as bivme-beat_expected_lv.cmake). Measured 2026-11-28: EF
# 0.391, peak 5.45 kPa, EDP 0.5 kPa, loop closure 1.5e-10 (issue 20: RV peak 3-5 kPa, not met).
set(EXPECT_STATUS completed)
set(EXPECT_EJECTION_FRACTION 0.37 0.41)
set(EXPECT_PEAK_PRESSURE_PA 5200 5700)
set(EXPECT_EDP_PA 495 505)
set(EXPECT_ISOVOLUMIC_DRIFT 0 0.001)
set(EXPECT_LOOP_CLOSURE 0 0.005)
set(EXPECT_FIBER_STRETCH_MIN 0.50 0.56)
set(EXPECT_FIBER_STRETCH_MAX 1.28 1.37)
set(EXPECT_WALL_VOLUME_CHANGE 0 0.0105)
