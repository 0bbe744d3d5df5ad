# Measured 2026-11-21: completed, 20 steps, 4 rejected (the step across the jump is cut), wall
# volume change 0.30 %.
set(HARD_ALLOWED completed failed)
set(HARD_VALUES "wall volume change|total_volume_m3,max_abs_relative_change|0|0.01"
                "rejected steps happened (the jump was cut)|rejected_steps|8|7.5")
