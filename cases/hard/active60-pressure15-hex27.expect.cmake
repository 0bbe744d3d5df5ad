set(HARD_ALLOWED completed failed)
set(HARD_VALUES "wall volume change|total_volume_m3,max_abs_relative_change|0|1e-4")
# Measured 2026-11-28: 208 hex27, completed in 13 load steps, 206 Newton iterations, 56 multiplier updates, wall
# volume change 1.5e-9 (max |Theta - 1| 9.1e-7), 91 s beside another run.
