"""Plots of the heart case (cases/heart/run.sh, step 5), from OUT/sim/globals.csv (and
OUT/scar/globals.csv when the scarred run exists), in the units cardiologists read:

  pv_loop_mmhg.png/.svg  pressure-volume loop of every beat, mmHg and ml, the passive inflation
                         before the first contraction (the ventricle's EDPVR: the atrial pressure
                         rises quasi-statically) and the last beat's end-diastolic and
                         end-systolic points
  espvr.png/.svg         (when OUT/occlusion exists: lv_beat_occlusion.yaml, the same beats at
                         lower preloads) every loop of both runs with their end-systolic points,
                         the ESPVR fitted through them, P_es = E_es (V_es - V_0) by least squares,
                         and the EDPVR; espvr.json holds E_es (mmHg/ml), V_0 (ml), r^2 and the points
  wiggers.png/.svg       Wiggers diagram: LV, aortic and atrial pressure (mmHg) and LV volume
                         (ml) against time, the four phases shaded, valve events marked
                         (MC mitral closes, AO aortic opens, AC aortic closes, MO mitral opens)
  pv_loop_scar_mmhg.png/.svg  healthy and scarred loops (when OUT/scar exists)
  pv_loop_biv_mmhg.png/.svg   LV and RV loops of a biventricular run (OUT/biv: the phantom's
                         biv_beat.yaml; or SIM itself when it has RV columns: a biventricular image
                         through run_image.sh), the passive inflation dotted
  bullseye.png/.svg      AHA 17-segment bull's-eye of the fibre strain from end diastole to end
                         systole of the last beat (frames nearest the mitral and aortic closures),
                         with the mean over the scar segment and over the remote wall when the mesh
                         has a `scar` cell field; bullseye_scar for the scarred run;
                         regional_strain.json holds the numbers

    /usr/bin/python3 cases/heart/plot_heart.py OUT [SIM] [--no-regional]
SIM: the healthy run's folder (default OUT/sim). --no-regional: no bull's-eye (its segments assume
the phantom's long axis along z; cases/heart/run_image.sh passes it for patient images). Needs numpy and matplotlib (Debian
python3-numpy, python3-matplotlib). Exits non-zero when a column is missing or a plot was not
written (ctest case.heart.plots runs it on case.heart.quick's results)."""
import json
import os
import re
import struct
import sys
import zlib
import xml.etree.ElementTree as ET

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


def biv_loops(g, out, figure="pv_loop_biv_mmhg", title="Biventricular pressure-volume loops"):
    """Both ventricles' loops of a biventricular run (OUT/biv: biv_beat.yaml; the simulation of a
    biventricular label image, run_image.sh), mmHg and ml."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for name, colour in (("lv", "#c0392b"), ("rv", "#2e6da4")):
        v, p, phase = g[name + "_volume"] * 1e6, g[name + "_pressure"] / MMHG, g[name + "_phase"].astype(int)
        started = np.cumsum(phase != 0) > 0  # from the first contraction on
        ax.plot(v[~started], p[~started], ":", lw=1.0, color=colour)
        ax.plot(v[started], p[started], "-", lw=1.6, color=colour, label=name.upper())
    ax.set_xlabel("volume (ml)")
    ax.set_ylabel("pressure (mmHg)")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    ax.grid(alpha=0.3)
    save(fig, out, figure)


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


def appended_block(raw, at):
    """The bytes of one appended array: zlib or LZ4 blocks (header [blocks, block size, last size,
    compressed sizes...], UInt64) as adamss writes them (output.compression), or one raw block
    [size] (output.compression: none, and older frames)."""
    head = raw[:4096]
    lz4 = b'compressor="vtkLZ4DataCompressor"' in head
    if not lz4 and b'compressor="vtkZLibDataCompressor"' not in head:
        size = struct.unpack_from("<Q", raw, at)[0]
        return raw[at + 8:at + 8 + size]
    if lz4:
        try:
            import lz4.block as lz4block
        except ImportError:
            sys.exit("plot_heart.py: this frame is LZ4-compressed (output.compression: lz4) and the "
                     "Python module lz4 is missing (Debian: python3-lz4)")
    blocks, block_size, last_size = struct.unpack_from("<3Q", raw, at)
    sizes = struct.unpack_from("<%dQ" % blocks, raw, at + 24)
    out, pos = [], at + 24 + 8 * blocks
    for k, size in enumerate(sizes):
        chunk = raw[pos:pos + size]
        if lz4:
            full = last_size if (k == blocks - 1 and last_size) else block_size
            out.append(lz4block.decompress(chunk, uncompressed_size=full))
        else:
            out.append(zlib.decompress(chunk))
        pos += size
    return b"".join(out)


def read_vtu(path):
    """The appended arrays of an adamss frame: {name: array of shape (n, components)}."""
    raw = open(path, "rb").read()
    start = raw.index(b'<AppendedData encoding="raw">')
    base = raw.index(b"_", start) + 1
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)" NumberOfComponents="(\d+)" format="appended" '
                         r'offset="(\d+)"/>', raw[:start].decode()):
        typ, name, comps, off = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
        dtype = {"Float64": "<f8", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1"}[typ]
        arrays[name] = np.frombuffer(appended_block(raw, base + off), dtype=dtype).reshape(-1, comps)
    return arrays


def frame_at(sim, t):
    """The frame of sim/series.pvd nearest to time t: (its time, its arrays)."""
    series = ET.parse(os.path.join(sim, "series.pvd")).getroot().iter("DataSet")
    best = min(((float(d.get("timestep")), d.get("file")) for d in series), key=lambda tf: abs(tf[0] - t))
    return best[0], read_vtu(os.path.join(sim, best[1]))


def aha_segments(points, conn):
    """AHA 17-segment index (1..17) of each element from its reference centroid. The long axis is
    z (base plane at the largest z, apex at the smallest): basal, mid, apical thirds down to 90 %
    of the length, apex cap (17) below. Around the axis, anterior = +y and septal = -x (an LV-only
    model has no septum: the convention fixes where it would be): basal and mid rings of six 60 deg
    segments starting with anterior (1 / 7) counter-clockwise seen from the apex, apical ring of
    four 90 deg segments (13 anterior, 14 septal, 15 inferior, 16 lateral)."""
    c = points[conn].mean(axis=1)
    z0, z1 = points[:, 2].max(), points[:, 2].min()
    depth = (z0 - c[:, 2]) / (z0 - z1)
    theta = np.degrees(np.arctan2(c[:, 1] - points[:, 1].mean(), c[:, 0] - points[:, 0].mean()))
    seg = np.full(len(c), 17)
    six = (np.floor(np.mod(theta - 60.0, 360.0) / 60.0)).astype(int)
    four = (np.floor(np.mod(theta - 45.0, 360.0) / 90.0)).astype(int)
    seg[depth < 0.9] = 13 + four[depth < 0.9]
    seg[depth < 0.65] = 7 + six[depth < 0.65]
    seg[depth < 0.35] = 1 + six[depth < 0.35]
    return seg


def last_beat_times(g):
    """End diastole and end systole of the last complete beat (the last mitral closure that an
    aortic closure follows, and that aortic closure), s; None without one (a run stopped in its
    first ejection)."""
    phase, t = g["lv_phase"].astype(int), g["t"]
    mc = [t[i] for i in range(1, len(t)) if phase[i - 1] == 0 and phase[i] == 1]
    ac = [t[i] for i in range(1, len(t)) if phase[i - 1] == 2 and phase[i] == 3]
    done = [m for m in mc if any(a > m for a in ac)]
    if not done:
        return None
    return done[-1], min(a for a in ac if a > done[-1])


def regional_strain(sim, g):
    """Fibre strain from end diastole to end systole per element (lambda_ES / lambda_ED - 1, the
    frames' fibre_stretch nearest to the valve events), its AHA segments, and the scar field of
    the frames when the mesh has one."""
    times = last_beat_times(g)
    if times is None:
        return None
    (t_ed, ed), (t_es, es) = frame_at(sim, times[0]), frame_at(sim, times[1])
    strain = es["fibre_stretch"][:, 0] / ed["fibre_stretch"][:, 0] - 1.0
    conn = ed["connectivity"][:, 0].reshape(len(strain), -1)
    seg = aha_segments(ed["Points"], conn)
    scar = ed["scar"][:, 0] > 0.5 if "scar" in ed else None
    return {"t_ed": t_ed, "t_es": t_es, "strain": strain, "segment": seg, "scar": scar}


def bullseye(r, out, name, title):
    """AHA bull's-eye of the mean fibre strain per segment (%), anterior at the top, septal left."""
    from matplotlib.patches import Wedge
    means = {k: 100.0 * r["strain"][r["segment"] == k].mean() for k in range(1, 18) if (r["segment"] == k).any()}
    lim = max(5.0, max(abs(v) for v in means.values()))
    cmap, norm = plt.get_cmap("RdBu_r"), matplotlib.colors.Normalize(-lim, lim)
    fig, ax = plt.subplots(figsize=(5.2, 4.6))
    rings = {1: (3.0, 4.0, 6, 60.0), 7: (2.0, 3.0, 6, 60.0), 13: (1.0, 2.0, 4, 45.0)}
    for first, (r0, r1, n, start) in rings.items():
        width = 360.0 / n
        for k in range(n):
            segment, a0 = first + k, start + k * width
            value = means.get(segment)
            ax.add_patch(Wedge((0, 0), r1, a0, a0 + width, width=r1 - r0, ec="k", lw=0.8,
                               fc="0.85" if value is None else cmap(norm(value))))
            mid = np.radians(a0 + width / 2)
            label = "%d\n%s" % (segment, "-" if value is None else "%.1f" % value)
            ax.text(0.5 * (r0 + r1) * np.cos(mid), 0.5 * (r0 + r1) * np.sin(mid), label, ha="center", va="center",
                    fontsize=7)
    v17 = means.get(17)
    ax.add_patch(matplotlib.patches.Circle((0, 0), 1.0, ec="k", lw=0.8, fc="0.85" if v17 is None else cmap(norm(v17))))
    ax.text(0, 0, "17\n%s" % ("-" if v17 is None else "%.1f" % v17), ha="center", va="center", fontsize=7)
    ax.set_xlim(-4.3, 4.3)
    ax.set_ylim(-4.3, 4.3)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.text(0, 4.15, "anterior", ha="center", fontsize=8)
    ax.text(-4.25, 0, "septal", ha="center", va="center", rotation=90, fontsize=8)
    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.8,
                 label="fibre strain ED to ES (%)")
    text = title + "\nED t = %.0f ms, ES t = %.0f ms" % (1e3 * r["t_ed"], 1e3 * r["t_es"])
    if r["scar"] is not None and r["scar"].any():
        text += "\nscar %.1f %%, remote %.1f %%" % (100 * r["strain"][r["scar"]].mean(),
                                                  100 * r["strain"][~r["scar"]].mean())
    ax.set_title(text, fontsize=9)
    save(fig, out, name)
    return means


def es_points(summary_path):
    """(ESV ml, ESP mmHg) of every completed beat in a run's summary.json."""
    with open(summary_path) as f:
        beats_ = json.load(f)["cavities"]["lv"].get("per_beat", [])
    return [(1e6 * b["esv_m3"], b["esp_Pa"] / MMHG) for b in beats_]


def fit_espvr(points):
    """Least-squares line P = E_es (V - V_0) through (V, P); None when the volumes span < 5 %."""
    v, p = np.array([q[0] for q in points]), np.array([q[1] for q in points])
    if len(v) < 2 or np.ptp(v) < 0.05 * np.mean(v):
        return None
    slope, intercept = np.polyfit(v, p, 1)
    fitted = slope * v + intercept
    r2 = 1.0 - np.sum((p - fitted) ** 2) / max(np.sum((p - p.mean()) ** 2), 1e-300)
    return {"Ees_mmHg_per_ml": float(slope), "V0_ml": float(-intercept / slope), "r2": float(r2),
            "points": [{"esv_ml": float(a), "esp_mmHg": float(b)} for a, b in points]}


def espvr(g, go, sim, out):
    """PV loops of the baseline and occlusion runs with the fitted ESPVR; writes espvr.json."""
    points = es_points(os.path.join(sim, "summary.json")) + es_points(os.path.join(out, "occlusion", "summary.json"))
    fit = fit_espvr(points)
    if fit is None:
        sys.exit("plot_heart.py: the end-systolic points %s span too little volume for an ESPVR" % points)
    fig, ax = plt.subplots(figsize=(8.4, 4.6))
    b = beats(g, None)
    ax.plot(g["lv_volume"][b == 0] * 1e6, g["lv_pressure"][b == 0] / MMHG, "-", lw=1.0, color="0.35",
            label="passive inflation (EDPVR)")
    for run, data, style in (("baseline", g, "-"), ("occlusion", go, "--")):
        bb = beats(data, None)
        for k in range(1, bb.max() + 1):
            sel = bb == k
            ax.plot(data["lv_volume"][sel] * 1e6, data["lv_pressure"][sel] / MMHG, style, lw=1.3,
                    label="%s beat %d" % (run, k))
    pv = np.array([[q["esv_ml"], q["esp_mmHg"]] for q in fit["points"]])
    ax.plot(pv[:, 0], pv[:, 1], "ks", ms=5, label="end-systolic points")
    vv = np.linspace(max(fit["V0_ml"], 0.0), pv[:, 0].max() * 1.25, 50)
    ax.plot(vv, fit["Ees_mmHg_per_ml"] * (vv - fit["V0_ml"]), "k-", lw=1.0,
            label="ESPVR: E_es %.1f mmHg/ml, V_0 %.2f ml" % (fit["Ees_mmHg_per_ml"], fit["V0_ml"]))
    ax.set_xlabel("LV volume (ml)")
    ax.set_ylabel("LV pressure (mmHg)")
    ax.set_title("Loops at three preloads and the ESPVR")
    ax.set_ylim(bottom=0)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, frameon=False)
    ax.grid(alpha=0.3)
    save(fig, out, "espvr")
    with open(os.path.join(out, "espvr.json"), "w") as f:
        json.dump(fit, f, indent=2)
    return fit


def main(out, sim=None, regional_plots=True):
    g = read_globals(os.path.join(sim or os.path.join(out, "sim"), "globals.csv"))
    for col in ("lv_volume", "lv_pressure", "lv_aortic_pressure", "lv_atrial_pressure", "lv_phase"):
        if col not in g:
            sys.exit("plot_heart.py: %s/sim/globals.csv has no column %s" % (out, col))
    sim = sim or os.path.join(out, "sim")
    pv_loop(g, out)
    wiggers(g, out)
    written = ["pv_loop_mmhg", "wiggers"]
    if "rv_volume" in g and "rv_pressure" in g and "rv_phase" in g:  # a biventricular image (run_image.sh)
        biv_loops(g, out, "pv_loop_biv_mmhg", "Pressure-volume loops of both ventricles")
        written.append("pv_loop_biv_mmhg")
    regional = {}
    r = regional_strain(sim, g) if regional_plots else None
    if r is not None:
        regional["healthy"] = {"segments_percent": bullseye(r, out, "bullseye", "healthy")}
        if r["scar"] is not None and r["scar"].any():
            regional["healthy"]["scar_region_percent"] = 100 * r["strain"][r["scar"]].mean()
            regional["healthy"]["remote_percent"] = 100 * r["strain"][~r["scar"]].mean()
        written.append("bullseye")
    scar = os.path.join(out, "scar", "globals.csv")
    if os.path.exists(scar):
        gs = read_globals(scar)
        scar_loops(g, gs, out)
        written.append("pv_loop_scar_mmhg")
        rs = regional_strain(os.path.join(out, "scar"), gs)
        if rs is not None:
            regional["scar"] = {"segments_percent": bullseye(rs, out, "bullseye_scar", "apical-anterior scar")}
            if rs["scar"] is not None and rs["scar"].any():
                regional["scar"]["scar_region_percent"] = 100 * rs["strain"][rs["scar"]].mean()
                regional["scar"]["remote_percent"] = 100 * rs["strain"][~rs["scar"]].mean()
            written.append("bullseye_scar")
    biv = os.path.join(out, "biv", "globals.csv")
    if os.path.exists(biv):
        gb = read_globals(biv)
        for col in ("lv_volume", "lv_pressure", "lv_phase", "rv_volume", "rv_pressure", "rv_phase"):
            if col not in gb:
                sys.exit("plot_heart.py: %s has no column %s" % (biv, col))
        biv_loops(gb, out)
        written.append("pv_loop_biv_mmhg")
    occlusion = os.path.join(out, "occlusion", "globals.csv")
    if os.path.exists(occlusion):
        fit = espvr(g, read_globals(occlusion), sim, out)
        written.append("espvr")
        print("plot_heart.py: ESPVR E_es = %.2f mmHg/ml, V_0 = %.3f ml (r^2 %.4f, %d end-systolic points)"
              % (fit["Ees_mmHg_per_ml"], fit["V0_ml"], fit["r2"], len(fit["points"])))
    with open(os.path.join(out, "regional_strain.json"), "w") as f:
        json.dump(regional, f, indent=2)
    for n in written:
        for ext in ("png", "svg"):
            if os.path.getsize(os.path.join(out, n + "." + ext)) == 0:
                sys.exit("plot_heart.py: %s.%s is empty" % (n, ext))
    print("plot_heart.py: wrote " + ", ".join(n + ".png/.svg" for n in written) + " in " + out)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--no-regional"]
    main(args[0], args[1] if len(args) > 1 else None, "--no-regional" not in sys.argv)
