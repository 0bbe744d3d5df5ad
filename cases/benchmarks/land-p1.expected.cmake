# Land et al. 2015 problem 1 (shared REFERENCES.md §1): deformed z of the tip (10, 0.5, 1) mm,
# reference 4.17 mm (converged codes 4.151-4.185 mm); the acceptance band is 1 % of it.
# Measured 2026-11-21 on the 80 x 4 x 4 hexahedral box: 4.1533 mm (-0.40 %), relative volume
# change 1.3e-6, 24 load steps, 117 Newton iterations.
set(EXPECT_VALUES
  "tip z (m)|probes,tip,2|4.17e-3|4.17e-5"
  "tip y (m), symmetry plane|probes,tip,1|0.5e-3|1e-9"
  "max relative volume change|total_volume_m3,max_abs_relative_change|0|1e-4")
