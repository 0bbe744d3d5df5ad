set(HARD_ALLOWED completed unstable failed)
set(HARD_CGAL_MESH "2mm;--cgal-no-perturb;--cgal-no-exude")
set(HARD_VALUES "wall volume change|total_volume_m3,max_abs_relative_change|0|0.05")
