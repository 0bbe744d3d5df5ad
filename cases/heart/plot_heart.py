"""Plots of the heart case (cases/heart/run.sh, step 5), from OUT/sim/globals.csv (and
OUT/scar/globals.csv when the scarred run exists), in the units cardiologists read:

  pv_loop_mmhg.png/.svg  pressure-volume loop of every beat, mmHg and ml, the passive inflation
                         before the first contraction (the ventricle's EDPVR: the atrial pressure
                         rises quasi-statically) and the last beat's end-diastolic and
                         end-systolic points (ESPVR needs loops at several loads: not drawn)
  wiggers.png/.svg       Wiggers diagram: LV, aortic and atrial pressure (mmHg) and LV volume
                         (ml) against time, the four phases shaded, valve events marked
                         (MC mitral closes, AO aortic opens, AC aortic closes, MO mitral opens)
  pv_loop_scar_mmhg.png/.svg  healthy and scarred loops (when OUT/scar exists)

    /usr/bin/python3 cases/heart/plot_heart.py OUT [SIM]
SIM: the healthy run's folder (default OUT/sim). Needs numpy and matplotlib (Debian
python3-numpy, python3-matplotlib). Exits non-zero when a column is missing or a plot was not
written (ctest case.heart.plots runs it on case.heart.quick's results)."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MMHG = 133.322387415
PHASES = ["filling", "isovolumic contraction", "ejection", "isovolumic relaxation"]
COLOURS = ["#dbe9f6", "#fde0c5", "#f8c9c9", "#e4d7f0"]
EVENTS = {(0, 1): "MC", (1, 2): "AO", (2, 3): "AC", (3, 0): "MO"}


def read_globals(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {n: data[:, i] for i, n in enumerate(names)}


def save(fig, out, name):
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out, name + "." + ext), dpi=130)
    plt.close(fig)


def beats(g, period):
    """Beat index of each row: the beat whose contraction comes next (cut at each MC)."""
    phase = g["lv_phase"].astype(int)
    idx, b = np.zeros(len(phase), dtype=int), 0
    for i in range(1, len(phase)):
        if phase[i - 1] == 0 and phase[i] == 1:
            b += 1
        idx[i] = b
    return idx


def pv_loop(g, out):
    v, p, phase = g["lv_volume"] * 1e6, g["lv_pressure"] / MMHG, g["lv_phase"].astype(int)
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    b = beats(g, None)
    # Before the first contraction the relaxed ventricle is inflated quasi-statically by the rising
    # atrial pressure: that curve is its end-diastolic pressure-volume relation (EDPVR).
    first = b == 0
    ax.plot(v[first], p[first], "o-", ms=2.5, lw=1.0, color="0.35", label="passive inflation (EDPVR)")
    for k in range(1, b.max() + 1):
        sel = b == k
        ax.plot(v[sel], p[sel], "-", lw=1.6, label="beat %d" % k)
    for i in range(1, len(phase)):
        if b[i] == b.max() and (phase[i - 1], phase[i]) in ((0, 1), (2, 3)):
            ax.plot(v[i], p[i], "ks", ms=5)
            ax.annotate("ED" if phase[i] == 1 else "ES", (v[i], p[i]), textcoords="offset points", xytext=(5, 5))
    ax.set_xlabel("LV volume (ml)")
    ax.set_ylabel("LV pressure (mmHg)")
    ax.set_title("Pressure-volume loops")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    ax.grid(alpha=0.3)
    save(fig, out, "pv_loop_mmhg")


def wiggers(g, out):
    t = g["t"] * 1e3
    phase = g["lv_phase"].astype(int)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.4), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or phase[i] != phase[start]:
            for ax in (top, bottom):
                ax.axvspan(t[start], t[min(i, len(t) - 1)], color=COLOURS[phase[start]], lw=0)
            start = i
    top.plot(t, g["lv_pressure"] / MMHG, "C3", lw=1.8, label="LV")
    top.plot(t, g["lv_aortic_pressure"] / MMHG, "C0", lw=1.4, label="aortic")
    top.plot(t, g["lv_atrial_pressure"] / MMHG, "C2", lw=1.2, label="atrial")
    bottom.plot(t, g["lv_volume"] * 1e6, "k", lw=1.6)
    for i in range(1, len(phase)):
        ev = EVENTS.get((phase[i - 1], phase[i]))
        if ev:
            for ax in (top, bottom):
                ax.axvline(t[i], color="0.35", lw=0.8, ls="--")
            top.annotate(ev, (t[i], 1.0), xycoords=("data", "axes fraction"), xytext=(2, -12),
                         textcoords="offset points", fontsize=8)
    top.set_ylabel("pressure (mmHg)")
    top.legend(loc="center right", fontsize=8, framealpha=0.9)
    top.set_title("Wiggers diagram")
    bottom.set_ylabel("LV volume (ml)")
    bottom.set_xlabel("time (ms)")
    handles = [matplotlib.patches.Patch(color=c, label=n) for c, n in zip(COLOURS, PHASES)]
    bottom.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.32), fontsize=8, ncol=4, frameon=False)
    save(fig, out, "wiggers")


def scar_loops(g, s, out):
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for data, name, style in ((g, "healthy", "C0-"), (s, "scar", "C3-")):
        last = beats(data, None) == beats(data, None).max()
        ax.plot(data["lv_volume"][last] * 1e6, data["lv_pressure"][last] / MMHG, style, lw=1.6,
                label=name + " (last beat)")
    ax.set_xlabel("LV volume (ml)")
    ax.set_ylabel("LV pressure (mmHg)")
    ax.set_title("PV loops: healthy and apical-anterior scar")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "pv_loop_scar_mmhg")


def main(out, sim=None):
    g = read_globals(os.path.join(sim or os.path.join(out, "sim"), "globals.csv"))
    for col in ("lv_volume", "lv_pressure", "lv_aortic_pressure", "lv_atrial_pressure", "lv_phase"):
        if col not in g:
            sys.exit("plot_heart.py: %s/sim/globals.csv has no column %s" % (out, col))
    pv_loop(g, out)
    wiggers(g, out)
    written = ["pv_loop_mmhg", "wiggers"]
    scar = os.path.join(out, "scar", "globals.csv")
    if os.path.exists(scar):
        scar_loops(g, read_globals(scar), out)
        written.append("pv_loop_scar_mmhg")
    for n in written:
        for ext in ("png", "svg"):
            if os.path.getsize(os.path.join(out, n + "." + ext)) == 0:
                sys.exit("plot_heart.py: %s.%s is empty" % (n, ext))
    print("plot_heart.py: wrote " + ", ".join(n + ".png/.svg" for n in written) + " in " + out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None)
