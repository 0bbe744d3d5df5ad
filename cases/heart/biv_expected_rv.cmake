# Acceptance ranges of the biventricular beat's RV (cases/heart/biv_beat.yaml): human RV values
# (peak systolic pressure 3-5 kPa, i.e. 20-40 mmHg, the range issue 20 asks of the biv-me heart;
# EF 40-70 %; right atrial filling pressure 0.5 kPa given), the loop and beat checks of the LV.
# The fibre-stretch and wall-volume keys are the whole heart's, as for the LV.
set(EXPECT_STATUS completed)
set(EXPECT_EJECTION_FRACTION 0.40 0.70)
set(EXPECT_PEAK_PRESSURE_PA 3000 5000)
set(EXPECT_EDP_PA 200 1000)
set(EXPECT_ISOVOLUMIC_DRIFT 0 0.005)
set(EXPECT_LOOP_CLOSURE 0 0.02)
set(EXPECT_BEATS 2)
set(EXPECT_BEAT_TO_BEAT_CHANGE 0 0.02)
set(EXPECT_FIBER_STRETCH_MIN 0.55 1.0)
set(EXPECT_FIBER_STRETCH_MAX 1.0 1.5)
set(EXPECT_WALL_VOLUME_CHANGE 0 0.015)
