# Regression bands of the biv-me beat's RV (as bivme-beat_expected_lv.cmake). Measured 2026-11-29: EF
# 0.453, peak 4.73 kPa, EDP 0.5 kPa; the peak band lies inside issue 20's 3-5 kPa.
include(${CMAKE_CURRENT_LIST_DIR}/bivme-beat_expected_lv.cmake)
set(EXPECT_EJECTION_FRACTION 0.43 0.475)
set(EXPECT_PEAK_PRESSURE_PA 4500 4950)
set(EXPECT_EDP_PA 495 505)
