set(HARD_ALLOWED completed)
set(HARD_VALUES "volume change|total_volume_m3,max_abs_relative_change|0|1e-5")
# Measured 2026-11-28: completed in 3 load steps, 18 Newton iterations, 4 multiplier updates, volume change 9.5e-7, 0.2 s.
