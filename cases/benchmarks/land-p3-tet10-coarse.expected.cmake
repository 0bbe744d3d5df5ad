# Land et al. 2015 problem 3 on the coarse tet10 ellipsoid ([12, 6, 2], 792 tet10; issue 23). No
# published value is pinned here (REFERENCES.md gives none for problem 3). The apex positions are
# held to the finer [24, 12, 3] tet10 run of the convergence table (cases/benchmarks/README.md:
# endo -11.949 mm, epi -15.451 mm) within 0.3 mm (2.5 %); the midwall twist near the base to that
# run's -6.1 deg within 1 deg; the twist at midwall_2, which this mesh does not resolve (the fine
# mesh gives -18.7 deg), is a regression record of this mesh within 1.5 deg.
# Measured 2026-11-27 (one thread): endo -11.884 mm, epi -15.471 mm, twists midwall_1..4 -38.3,
# -23.5, -15.6, -6.16 deg, wall volume change 7.2e-9, 21 load steps, 203 Newton iterations,
# 35 multiplier updates, 28 s.
set(EXPECT_VALUES
  "endo apex z (m): contraction lifts the apex from -17 mm|probes,endo_apex,2|-11.949e-3|0.3e-3"
  "epi apex z (m)|probes,epi_apex,2|-15.451e-3|0.3e-3"
  "midwall twist near the base (deg)|probe_details,midwall_4,twist_about_z_deg|-6.1|1.0"
  "midwall twist at midwall_2 (deg), this mesh's record|probe_details,midwall_2,twist_about_z_deg|-23.46|1.5"
  "max relative wall volume change|total_volume_m3,max_abs_relative_change|0|1e-5")
