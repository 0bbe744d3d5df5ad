# Measured 2026-11-21: completed in 46 load steps; the free edge folds over to x = -4.1 mm,
# z = 4.6 mm; wall volume change 0.26 %.
set(HARD_ALLOWED completed failed)
set(HARD_VALUES "wall volume change|total_volume_m3,max_abs_relative_change|0|0.01"
                "free edge lifted (m)|probes,free_edge,2|0.0046|0.002")
