"""A heart beat's pressure-volume loop from Python: two beats of the idealised LV with a
circulation (cases/heart/lv_beat_quick.yaml: filling, isovolumic contraction, Windkessel
ejection, isovolumic relaxation), then the loop of the second beat and its metrics.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/heart_pv_loop.py [OUT]

Prints end-diastolic and end-systolic volume and pressure, stroke volume and ejection fraction
of the last beat (from the cavity's own valve events, as summary.json), and the loop in mmHg and
ml; with matplotlib installed it also saves OUT/pv_loop.png."""
import os
import sys

import numpy as np

import adamss

here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else "heart-pv-python"
r = adamss.run(os.path.join(here, "..", "..", "cases", "heart", "lv_beat_quick.yaml"), out, progress=True)
print("%s: %s, %d steps, %.1f s" % (r["name"], r["status"], r["steps"], r["wall_seconds"]))
lv = r["cavities"]["lv"]
for key in sorted(lv):
    if key.endswith("_m3"):
        print("  %-28s %10.3f ml" % (key[:-3], lv[key] * 1e6))
    elif key.endswith("_Pa"):
        print("  %-28s %10.2f mmHg" % (key[:-3], lv[key] / 133.322387415))
    else:
        print("  %-28s %10.4g" % (key, lv[key]))
g = r["globals"]
second = g["t"] >= 0.8  # the second beat (period 800 ms)
p_mmhg, v_ml = g["lv_pressure"][second] / 133.322387415, g["lv_volume"][second] * 1e6
print("  second beat: V %.2f .. %.2f ml, P %.1f .. %.1f mmHg, %d points" % (v_ml.min(), v_ml.max(), p_mmhg.min(),
                                                                           p_mmhg.max(), len(v_ml)))
np.savetxt(os.path.join(out, "pv_loop.csv"), np.column_stack([g["t"][second], v_ml, p_mmhg]), delimiter=",",
           header="t_s,volume_ml,pressure_mmHg", comments="")
print("  wrote", os.path.join(out, "pv_loop.csv"))
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(v_ml, p_mmhg, "-")
    ax.set_xlabel("LV volume (ml)")
    ax.set_ylabel("LV pressure (mmHg)")
    ax.set_title("Pressure-volume loop (second beat)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pv_loop.png"), dpi=120)
    print("  wrote", os.path.join(out, "pv_loop.png"))
except ImportError:
    pass
