"""ctest python.espvr: the ESPVR fit of cases/heart/plot_heart.py. End-systolic points on a known
line P = 90 (V - 0.8) (mmHg, ml) with small alternating errors give E_es and V_0 back within the
least-squares error; points spanning < 5 % of their volume are refused (no ESPVR from one load)."""
import os
import sys

sys.path.insert(0, os.path.join(sys.argv[1], "cases", "heart"))
import plot_heart  # noqa: E402

exact = [(v, 90.0 * (v - 0.8)) for v in (1.4, 1.5, 1.6, 1.7)]
fit = plot_heart.fit_espvr(exact)
assert abs(fit["Ees_mmHg_per_ml"] - 90.0) < 1e-9 and abs(fit["V0_ml"] - 0.8) < 1e-11, fit
assert abs(fit["r2"] - 1.0) < 1e-12, fit
noisy = [(v, p + (0.5 if k % 2 else -0.5)) for k, (v, p) in enumerate(exact)]
fit = plot_heart.fit_espvr(noisy)
assert abs(fit["Ees_mmHg_per_ml"] - 90.0) < 5.0 and abs(fit["V0_ml"] - 0.8) < 0.05 and fit["r2"] > 0.99, fit
assert plot_heart.fit_espvr([(1.60, 80.0), (1.62, 82.0)]) is None  # two beats at one load: 1 % apart
assert plot_heart.fit_espvr([(1.6, 80.0)]) is None
print("ESPVR fit: E_es %.3f mmHg/ml, V_0 %.4f ml from the noisy points" % (fit["Ees_mmHg_per_ml"], fit["V0_ml"]))
