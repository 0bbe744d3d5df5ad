# Land et al. 2015 problem 1 on 160 hex27 (Q2-P1disc, cases/benchmarks/land-p1-hex27.yaml): the
# issue-23 acceptance of quadratic elements, the tip within 0.1 % of 4.17 mm on <= 1 000 elements.
# Measured 2026-11-28: 4.16686 mm (-0.075 %), relative volume change 3.6e-7, 64 Newton, 8.6 s; after
# fed450c (the Q2-P1disc Hessians as one dense product) 4.16683 mm, 68 Newton, 6.4 s. The tip's y
# stays on the symmetry plane to the Newton tolerance, not to rounding: the dense product does
# not repeat a mirrored node's arithmetic exactly, and the 1e-6 relative residual leaves 4e-9 m.
set(EXPECT_VALUES
  "tip z (m)|probes,tip,2|4.17e-3|0.417e-5"
  "tip y (m), symmetry plane|probes,tip,1|0.5e-3|1e-7"
  "max relative volume change|total_volume_m3,max_abs_relative_change|0|1e-5")
