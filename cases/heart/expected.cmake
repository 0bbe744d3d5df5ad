# Expected values of the heart case (cases/heart/lv_beat.yaml on the 1 mm mesh) with their
# margins; checked by check.cmake at the end of run.sh. Measured 2026-11-21: LV cavity
# 2.364 ml at rest, 3.89 ml at end of filling (31 ms), 0.88 ml at end of contraction
# (80 ms), ejection fraction 0.774, wall volume change at most 4.3 %.
set(EXPECT_STATUS completed)
set(EXPECT_LV_VOLUME_INITIAL_ML 2.364 0.01)   # value, margin (voxelised cavity at 1 mm)
set(EXPECT_LV_VOLUME_MAX_ML 3.89 0.20)
set(EXPECT_LV_VOLUME_MIN_ML 0.88 0.20)
set(EXPECT_EJECTION_FRACTION 0.774 0.05)
set(EXPECT_WALL_VOLUME_CHANGE_MAX 0.06)        # |V - V0| / V0 of the myocardium, upper bound
