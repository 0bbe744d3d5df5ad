"""Land et al. 2015 problem 2 from Python: inflate the truncated ellipsoidal LV to 10 kPa and
print its inflation curve (cavity pressure against volume) and the deformed apex.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/land_problem2_inflation.py [OUT]

With matplotlib installed it also saves OUT/inflation.png. The same run is the ctest
python.land_p2 (tests/python/test_land_p2.py), which checks the apex against the reference."""
import os
import sys

import adamss

here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else "land-p2-python"
r = adamss.run(os.path.join(here, "..", "..", "cases", "benchmarks", "land-p2.yaml"), out)
print("%s: %s after %d load steps, %.1f s" % (r["name"], r["status"], r["steps"], r["wall_seconds"]))
for probe in ("endo_apex", "epi_apex"):
    print("  %s: z = %.3f mm (Land 2015 reference: %s)" % (probe, r["probes"][probe]["final_position"][2] * 1e3,
                                                          "-26.6 mm" if probe == "endo_apex" else "-28.3 mm"))
g = r["globals"]
print("  pressure (kPa)  cavity volume (ml)")
for p, v in zip(g["lv_pressure"], g["lv_volume"]):
    print("  %12.3f  %16.4f" % (p / 1e3, v * 1e6))
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(g["lv_volume"] * 1e6, g["lv_pressure"] / 133.322387415, "o-", ms=3)
    ax.set_xlabel("LV cavity volume (ml)")
    ax.set_ylabel("LV pressure (mmHg)")
    ax.set_title("Land 2015 problem 2: passive inflation")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "inflation.png"), dpi=120)
    print("  wrote", os.path.join(out, "inflation.png"))
except ImportError:
    pass
