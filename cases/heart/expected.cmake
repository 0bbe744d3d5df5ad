# Acceptance ranges of the heart case (cases/heart/lv_beat.yaml and lv_beat_quick.yaml), checked
# by check.cmake: the physiological ranges of the issue (EF 40-70 %, peak LV pressure 12-18 kPa,
# isovolumic volume held within 0.5 %, loop closed within 2 % after the second beat), plus sanity
# bounds; and the planning scenario (check_scar.cmake): the scarred EF lower than the healthy one.
set(EXPECT_STATUS completed)
set(EXPECT_EJECTION_FRACTION 0.40 0.70)
set(EXPECT_PEAK_PRESSURE_PA 12000 18000)
set(EXPECT_EDP_PA 500 2000)                  # end-diastolic (atrial) pressure, 1 kPa given
set(EXPECT_ISOVOLUMIC_DRIFT 0 0.005)
set(EXPECT_LOOP_CLOSURE 0 0.02)              # |V_end - EDV_1| / EDV_1, refilled after beat 2
set(EXPECT_BEATS 2)
set(EXPECT_BEAT_TO_BEAT_CHANGE 0 0.02)       # max(|EDV_2/EDV_1 - 1|, |ESV_2/ESV_1 - 1|)
set(EXPECT_FIBER_STRETCH_MIN 0.6 1.0)
set(EXPECT_FIBER_STRETCH_MAX 1.0 1.5)
set(EXPECT_WALL_VOLUME_CHANGE 0 0.01)        # |V - V0| / V0 of the myocardium (nearly incompressible, issue 23)
set(EXPECT_SCAR_EJECTION_FRACTION 0.15 0.70)
set(EXPECT_SCAR_EF_DROP_MIN 0.01)            # EF_healthy - EF_scar
