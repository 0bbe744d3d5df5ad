set(HARD_ALLOWED completed)
set(HARD_VALUES "volume change|total_volume_m3,max_abs_relative_change|0|0.001")
