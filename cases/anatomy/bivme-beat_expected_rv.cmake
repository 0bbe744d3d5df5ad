# Regression bands of the biv-me beat's RV (as bivme-beat_expected_lv.cmake). Measured 2026-11-29: EF
# 0.588, peak 4.05 kPa, EDP 0.5 kPa, loop closure 1.2e-4; the peak band lies inside issue 20's 3-5 kPa.
include(${CMAKE_CURRENT_LIST_DIR}/bivme-beat_expected_lv.cmake)
set(EXPECT_EJECTION_FRACTION 0.565 0.61)
set(EXPECT_PEAK_PRESSURE_PA 3850 4250)
set(EXPECT_EDP_PA 495 505)
