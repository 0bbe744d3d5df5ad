"""One picture of a heart run (issue 20: "mesh with fibres, end-diastole and end-systole"), drawn
with matplotlib alone (no OpenGL needed), from SIM/series.pvd, its frames and SIM/globals.csv:

  heart_views.png   three panels of the same long-axis cut through the wall:
                    1. the reference (unloaded) mesh, each visible face coloured by the helix angle
                       of its element's fibre against the frames' cardiac frame (alpha = atan(f.e_l /
                       f.e_c), deg: 0 circumferential, +90 along the long axis towards the base; e_l
                       is the long axis itself, where the rule fibres of
                       preprocess/fibres/rule_fibres.hpp use it projected onto the wall, so the two
                       agree where the wall is parallel to the axis and differ towards the apex)
                       with the projected fibre directions drawn on a subset of the faces that face
                       the viewer (the cut, and the endocardium seen through the cavity);
                    2. end diastole and 3. end systole of the last beat (the frames nearest to the
                       last mitral closure and the aortic closure after it), coloured by the fibre
                       stretch against the reference.
  heart_views.json  the frame times and the long-axis kinematics of that beat: the wall's length
                    along the long axis (from the highest node to the mean of the 20 lowest, the
                    apex) at end diastole and end systole and its relative change (a real ventricle
                    shortens by about 10-20 %), and how far the apex node (the lowest node of the
                    reference) moves along the axis from end diastole to end systole (mm, + towards
                    the base), and the median fibre stretch (against the reference) at both.

The cut: the plane through the mesh centroid that contains the long axis (the frames'
`longitudinal` field) and the direction from the LV wall's centroid to the RV free wall's
(`ventricle` field; an LV-only mesh takes the widest direction across the axis), so a
biventricular heart is cut through both cavities as in a four-chamber view. The elements whose
reference centroid lies behind the plane are kept and their boundary faces drawn back to front
(painter's order), lit by the face normal. The view looks at the cut face with the base up.

    /usr/bin/python3 cases/heart/render_heart.py SIM OUT_PNG   (the JSON beside OUT_PNG)

Exits non-zero with a message when a frame, a field or the beat's valve events are missing."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_heart  # noqa: E402

# Local faces of a tetrahedron (VTK 10) and a hexahedron (VTK 12), node order as VTK's.
FACES = {4: [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)],
         8: [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]}


def cells(frame):
    """Connectivity as an (n_cells, k) array; one element kind (tet4 or hex8) per mesh."""
    conn, offsets = frame["connectivity"][:, 0], frame["offsets"][:, 0]
    k = int(offsets[0])
    if k not in FACES or np.any(np.diff(offsets) != k):
        raise SystemExit("render_heart.py: only meshes of tet4 or of hex8 elements are drawn")
    return conn.reshape(-1, k)


def view_frame(frame, centres):
    """(e_x, e_y, e_z, origin) from the element centres: e_y the long axis (apex -> base), e_z the
    cut plane's normal (towards the viewer), e_x = e_y x e_z in the plane."""
    if "longitudinal" not in frame:
        raise SystemExit("render_heart.py: the frames have no `longitudinal` field (the long axis)")
    e_y = frame["longitudinal"].mean(axis=0)
    e_y /= np.linalg.norm(e_y)
    if "ventricle" in frame and np.any(frame["ventricle"][:, 0] > 0.5):
        rv = frame["ventricle"][:, 0] > 0.5
        across = centres[rv].mean(axis=0) - centres[~rv].mean(axis=0)
    else:
        flat = centres - centres.mean(axis=0)
        flat -= np.outer(flat @ e_y, e_y)
        across = np.linalg.svd(flat, full_matrices=False)[2][0]
    e_x = across - (across @ e_y) * e_y
    e_x /= np.linalg.norm(e_x)
    e_z = np.cross(e_x, e_y)
    return e_x, e_y, e_z, centres.mean(axis=0)


def visible_faces(conn, keep):
    """Boundary faces of the kept elements: (element index, node indices, interior node of the
    element to orient the face outwards)."""
    k = conn.shape[1]
    kept, ids = conn[keep], np.nonzero(keep)[0]
    faces, owners, inner = [], [], []
    for local in FACES[k]:
        faces.append(kept[:, local])
        owners.append(ids)
        rest = [i for i in range(k) if i not in local][0]
        inner.append(kept[:, rest])
    faces, owners, inner = np.vstack(faces), np.concatenate(owners), np.concatenate(inner)
    key = np.sort(faces, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    single = first[count == 1]
    return owners[single], faces[single], inner[single]


def draw(ax, x, basis, owners, faces, inner, values, cmap, vmin, vmax, fibres=None):
    """The faces projected on (e_x, e_y), back to front, shaded by |n . e_z|; returns the mappable."""
    e_x, e_y, e_z, origin = basis
    p = x - origin
    xy = np.stack([p @ e_x, p @ e_y], axis=-1)
    depth = p @ e_z
    tri = x[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    outward = np.einsum("ij,ij->i", normal, tri[:, 0] - x[inner]) > 0
    normal[~outward] *= -1
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    facing = normal @ e_z
    order = np.argsort(depth[faces].mean(axis=1))
    order = order[facing[order] > 0]
    colours = plt.get_cmap(cmap)(np.clip((values[owners[order]] - vmin) / (vmax - vmin), 0, 1))
    shade = 0.35 + 0.65 * facing[order]
    colours[:, :3] *= shade[:, None]
    ax.add_collection(PolyCollection(xy[faces[order]] * 1e3, facecolors=colours, edgecolors="none", linewidths=0))
    if fibres is not None:
        front = order[facing[order] > 0.6]
        cut = front[:: max(1, len(front) // 700)]
        centre = xy[faces[cut]].mean(axis=1) * 1e3
        f = fibres[owners[cut]]
        d = np.stack([f @ e_x, f @ e_y], axis=-1) * 1.6
        ax.add_collection(LineCollection(np.stack([centre - d, centre + d], axis=1), colors="k", linewidths=0.5))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("mm (across the cut)")
    ax.set_ylabel("mm (long axis, base up)")
    return plt.cm.ScalarMappable(norm=plt.Normalize(vmin, vmax), cmap=cmap)


def long_axis(frames, basis):
    """Wall length along the long axis (m) of each frame and the apex node's axial position (m)."""
    e_y, origin = basis[1], basis[3]
    apex = int(np.argmin((frames[0]["Points"] - origin) @ e_y))
    out = []
    for fr in frames:
        y = (fr["Points"] + fr["displacement"] - origin) @ e_y
        out.append((y.max() - np.sort(y)[:20].mean(), y[apex]))
    return out


def helix_angle(frame):
    f, c, l = frame["fibre"], frame["circumferential"], frame["longitudinal"]
    fc, fl = np.einsum("ij,ij->i", f, c), np.einsum("ij,ij->i", f, l)
    return np.degrees(np.arctan(fl / np.where(np.abs(fc) < 1e-12, 1e-12, fc)))


def main(sim, png):
    for name in ("globals.csv", "series.pvd"):
        if not os.path.isfile(os.path.join(sim, name)):
            raise SystemExit("render_heart.py: " + os.path.join(sim, name) + " not found (not a finished run folder?)")
    g = plot_heart.read_globals(os.path.join(sim, "globals.csv"))
    if "lv_phase" not in g:
        raise SystemExit("render_heart.py: " + sim + "/globals.csv has no lv_phase column (a run without an LV "
                         "circulation has no beat to draw)")
    times = plot_heart.last_beat_times(g)
    if times is None:
        raise SystemExit("render_heart.py: " + sim + "/globals.csv has no complete beat (no mitral closure "
                         "followed by an aortic closure)")
    (_, ref), (t_ed, ed), (t_es, es) = (plot_heart.frame_at(sim, 0.0), plot_heart.frame_at(sim, times[0]),
                                         plot_heart.frame_at(sim, times[1]))
    for name in ("fibre", "circumferential", "fibre_stretch"):
        if name not in ref:
            raise SystemExit("render_heart.py: the frames have no `" + name + "` field")
    conn = cells(ref)
    centres = ref["Points"][conn].mean(axis=1)
    basis = view_frame(ref, centres)
    keep = (centres - basis[3]) @ basis[2] <= 0.0
    owners, faces, inner = visible_faces(conn, keep)
    fig, axes = plt.subplots(1, 3, figsize=(16, 6.4))
    m = draw(axes[0], ref["Points"], basis, owners, faces, inner, helix_angle(ref), "coolwarm", -90, 90,
             fibres=ref["fibre"])
    fig.colorbar(m, ax=axes[0], shrink=0.8, label="fibre helix angle (deg)")
    axes[0].set_title("reference mesh (%d elements), fibres" % len(conn))
    for ax, t, fr, event, label in ((axes[1], t_ed, ed, times[0], "end diastole"),
                                    (axes[2], t_es, es, times[1], "end systole")):
        m = draw(ax, fr["Points"] + fr["displacement"], basis, owners, faces, inner, fr["fibre_stretch"][:, 0],
                 "viridis", 0.6, 1.2)
        fig.colorbar(m, ax=ax, shrink=0.8, label="fibre stretch")
        ax.set_title("%s, frame t = %.3f s (event %.3f s)" % (label, t, event))
    lim = [min(a.get_xlim()[0] for a in axes), max(a.get_xlim()[1] for a in axes)]
    ylim = [min(a.get_ylim()[0] for a in axes), max(a.get_ylim()[1] for a in axes)]
    for ax in axes:
        ax.set_xlim(lim)
        ax.set_ylim(ylim)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    (l_ed, a_ed), (l_es, a_es) = long_axis([ed, es], basis)
    kin = {"t_ed_frame_s": t_ed, "t_es_frame_s": t_es, "t_ed_event_s": times[0], "t_es_event_s": times[1],
           "long_axis_length_ed_m": l_ed, "long_axis_length_es_m": l_es, "long_axis_change": l_es / l_ed - 1.0,
           "apex_axial_motion_ed_to_es_m": a_es - a_ed,
           "fibre_stretch_median_ed": float(np.median(ed["fibre_stretch"][:, 0])),
           "fibre_stretch_median_es": float(np.median(es["fibre_stretch"][:, 0]))}
    with open(os.path.splitext(png)[0] + ".json", "w") as f:
        json.dump(kin, f, indent=2)
    print("render_heart.py: wrote %s (%d faces; ED frame %.3f s, ES frame %.3f s); long axis %.1f -> %.1f mm "
          "(%+.1f %%), apex %+.1f mm along the axis" % (png, len(faces), t_ed, t_es, 1e3 * l_ed, 1e3 * l_es,
                                                        100 * kin["long_axis_change"], 1e3 * (a_es - a_ed)))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2])
