"""ctest python.land_p2: Land et al. 2015 problem 2 (passive LV inflation to 10 kPa) run from
Python with the scene of cases/benchmarks/land-p2.yaml. Checks against REFERENCES.md section 1:
the deformed endocardial apex at z = -26.6 mm and the epicardial one at -28.3 mm, 2 % bands (as
cases/benchmarks/land-p2.expected.cmake); the inflation curve from globals: pressure ramps to
10 kPa, the cavity volume grows monotonically."""
import os
import sys
import tempfile

import numpy as np

import adamss

source = sys.argv[1]
out = tempfile.mkdtemp(prefix="adamss-python-land-p2-")
r = adamss.run(os.path.join(source, "cases/benchmarks/land-p2.yaml"), out,
               cache=os.path.join(out, "cache"))
assert r["status"] == "completed", r["reason"]
endo = r["probes"]["endo_apex"]["final_position"][2]
epi = r["probes"]["epi_apex"]["final_position"][2]
print("endo apex z %.4f mm, epi apex z %.4f mm, %d steps, %.1f s" % (endo * 1e3, epi * 1e3, r["steps"],
                                                                     r["wall_seconds"]))
assert abs(endo - -26.6e-3) <= 0.02 * 26.6e-3, endo
assert abs(epi - -28.3e-3) <= 0.02 * 28.3e-3, epi
g = r["globals"]
p, v = g["lv_pressure"], g["lv_volume"]
assert len(p) == r["steps"] + 1 and len(v) == len(p), (len(p), r["steps"])
assert abs(p[-1] - 10e3) < 1e-6 * 10e3, p[-1]
assert np.all(np.diff(p) > 0) and np.all(np.diff(v) > 0), "pressure and volume must grow together"
assert v[-1] > 1.5 * v[0], (v[0], v[-1])  # the cavity inflates
assert r["positions"].shape == r["reference_positions"].shape == (len(r["displacement"]), 3)
print("inflation curve: %d points, V %.3f -> %.3f ml" % (len(p), v[0] * 1e6, v[-1] * 1e6))
