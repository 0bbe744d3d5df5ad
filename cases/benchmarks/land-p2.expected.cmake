# Land et al. 2015 problem 2 (shared REFERENCES.md §1): deformed z of the endocardial apex,
# reference -26.6 mm (codes -26.9 ... -26.4), acceptance band 1 % of it (2 % before 2026-12-01); the epicardial apex,
# reference -28.3 mm (-28.5 ... -28.1), same band. Measured 2026-11-21 on the [24, 12, 3]
# hexahedral ellipsoid: endo -26.720 mm (+0.45 %), epi -28.397 mm (+0.34 %), relative wall volume
# change 4.1e-5, 40 load steps, 209 Newton iterations. 2026-11-28: the scene is now the coarser
# [16, 8, 2] with the penalty staged (continuation from 10 C): endo -26.853 mm (+0.95 %), epi
# -28.661 mm (+1.28 %), wall volume change 3.7e-5, 2 load steps, 31 Newton iterations, 0.3 s.
# 2026-11-29: BFGS updates (bfgs_max_updates 5): the same apices, 62 iterations on 19
# factorisations (31 without the updates). 2026-12-01: [16, 9, 2], the coarsest mesh with both
# apices within 1 % (issue 19's done-when), now the band: endo -26.780 mm (+0.68 %), epi
# -28.462 mm (+0.57 %), wall volume change 3.8e-5, 65 iterations on 21 factorisations.
set(EXPECT_VALUES
  "endo apex z (m)|probes,endo_apex,2|-26.6e-3|0.266e-3"
  "epi apex z (m)|probes,epi_apex,2|-28.3e-3|0.283e-3"
  "endo apex x (m), on the axis|probes,endo_apex,0|0|1e-9"
  "max relative wall volume change|total_volume_m3,max_abs_relative_change|0|1e-3"
  "operators factorised (BFGS)|reformations|21|6")
