# Land et al. 2015 problem 3. The paper's values are checked separately (issue 8: no tuning to a
# guess), so this file holds physical sanity bounds and the measured values as a regression record.
# Measured 2026-11-21 ([24, 12, 3] hexahedra, 20 load steps, 107 Newton iterations, 33 s):
# endo apex z -11.73 mm, epi apex z -15.37 mm, midwall twist -24.4 deg (near the apex, midwall_1)
# falling to -5.4 deg (midwall_4), wall volume change 0.24 %.
set(EXPECT_VALUES
  "endo apex z (m): contraction lifts the apex from -17 mm|probes,endo_apex,2|-11.73e-3|0.6e-3"
  "epi apex z (m)|probes,epi_apex,2|-15.37e-3|0.6e-3"
  "midwall twist near the apex (deg)|probe_details,midwall_1,twist_about_z_deg|-24.4|2.5"
  "midwall twist near the base (deg)|probe_details,midwall_4,twist_about_z_deg|-5.35|1.5"
  "max relative wall volume change|total_volume_m3,max_abs_relative_change|0|0.01")
