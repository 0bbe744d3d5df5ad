# Acceptance ranges of the heart case (cases/heart/lv_beat.yaml and lv_beat_quick.yaml), checked
# by check.cmake: the physiological ranges of the issue (EF 40-70 %, peak LV pressure 12-18 kPa,
# isovolumic volume held within 0.5 %, loop closed within 2 %), plus sanity bounds.
set(EXPECT_STATUS completed)
set(EXPECT_EJECTION_FRACTION 0.40 0.70)
set(EXPECT_PEAK_PRESSURE_PA 12000 18000)
set(EXPECT_EDP_PA 500 2000)                  # end-diastolic (atrial) pressure, 1 kPa given
set(EXPECT_ISOVOLUMIC_DRIFT 0 0.005)
set(EXPECT_LOOP_CLOSURE 0 0.02)
set(EXPECT_FIBER_STRETCH_MIN 0.6 1.0)
set(EXPECT_FIBER_STRETCH_MAX 1.0 1.5)
set(EXPECT_WALL_VOLUME_CHANGE 0 0.10)        # |V - V0| / V0 of the myocardium
