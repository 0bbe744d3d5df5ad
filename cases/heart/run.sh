#!/usr/bin/env bash
# The heart case, end to end: image -> mesh -> two simulated beats with a circulation, healthy
# and with an apical-anterior scar -> plots, report and checks.
# Usage: cases/heart/run.sh ADAMSS_BINARY OUTPUT_DIR
#   HEART_VOXEL (default 2.5mm; 1.25mm does not yet finish: the refilling after the beat stalls) sets the voxel size (the base plane z = 5 mm must be a whole
#   number of voxels: 0.5, 1, 1.25, 2.5 mm); HEART_CHECK=0 skips the physiology check.
#   HEART_SCAR=0 skips the scarred run; HEART_ESPVR=0 skips the lower-preload run (and the ESPVR);
#   HEART_BIV=0 skips the biventricular run (biv_unload.yaml unloaded into OUTPUT_DIR/biv_unload, then
#   biv_beat.yaml from that reference, results in OUTPUT_DIR/biv). `make heart HEART_IMAGE=phantom`
#   runs this script; plain `make heart` runs the real heart (run_image.sh on biv-me patient1).
# Writes OUTPUT_DIR/{summary.json, pv_loop.png, pressure_volume_time.png, pv_loop_scar.png,
# report.md}, the healthy simulation in OUTPUT_DIR/sim (series.pvd + frames/*.vtu, globals.csv)
# and the scarred one in OUTPUT_DIR/scar (its summary.json there).
set -euo pipefail
adamss=${1:?usage: run.sh ADAMSS_BINARY OUTPUT_DIR}
out=${2:?usage: run.sh ADAMSS_BINARY OUTPUT_DIR}
voxel=${HEART_VOXEL:-2.5mm}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
SECONDS=0

scar=${HEART_SCAR:-1}

echo "== 1/6 phantom: Land 2015 LV truncated ellipsoid, $voxel voxels, helix +60/-60 deg, apical-anterior scar segment"
"$adamss" phantom lv --voxel-size "$voxel" -o "$out/lv.nii.gz" \
  --fiber-out "$out/lv_fiber.nii.gz" --sheet-out "$out/lv_sheet.nii.gz" --helix-endo 60 --helix-epi -60 \
  --scar-out "$out/lv_scar.nii.gz" --scar-direction 0,1,-1 --scar-angle 30

echo "== 2/6 mesh: tet6m, phantom fibres, closed LV cavity (label 2) with its lid, base plane tag, scar cell field"
"$adamss" mesh "$out/lv.nii.gz" --solid 1 --topology tet6m \
  --fiber "$out/lv_fiber.nii.gz" --sheet "$out/lv_sheet.nii.gz" --cell-field scar="$out/lv_scar.nii.gz" \
  --cavity lv=2 --tag-plane base=z:5mm -o "$out/lv.h5"
"$adamss" info "$out/lv.h5" --json > "$out/mesh_info.json"
"$adamss" info "$out/lv.h5"

echo "== 3/6 simulation, healthy: two beats (filling, IVC, Windkessel ejection, IVR, refilling), see lv_beat.yaml"
cp "$here/lv_beat.yaml" "$out/lv_beat.yaml"
t_sim=$SECONDS
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" run "$out/lv_beat.yaml" -o "$out/sim" --progress-interval 5s
t_sim=$((SECONDS - t_sim))
cp "$out/sim/summary.json" "$out/summary.json"

echo "== 4/6 simulation, scarred: the same two beats with the scar segment (no active tension, k_ij x10), see lv_beat_scar.yaml"
t_scar=0
if [[ "$scar" == 1 ]]; then
  cp "$here/lv_beat_scar.yaml" "$out/lv_beat_scar.yaml"
  t_scar=$SECONDS
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" run "$out/lv_beat_scar.yaml" -o "$out/scar" --progress-interval 5s
  t_scar=$((SECONDS - t_scar))
else
  echo "skipped (HEART_SCAR=0)"
fi

echo "== 4b/6 simulation, lower preloads: the healthy beats at atrial pressures 0.6 and 0.3 kPa (a caval occlusion), for the ESPVR; see lv_beat_occlusion.yaml"
if [[ "${HEART_ESPVR:-1}" == 1 ]]; then
  cp "$here/lv_beat_occlusion.yaml" "$out/lv_beat_occlusion.yaml"
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" run "$out/lv_beat_occlusion.yaml" -o "$out/occlusion" --progress-interval 5s
else
  echo "skipped (HEART_ESPVR=0)"
fi

# unload_and_beat UNLOAD_SCENE TOLERANCE BEAT_SCENE NAME PROGRESS: `adamss unload` of the end-diastolic
# image's scene into OUT/NAME_unload, then the beat from that unloaded reference into OUT/NAME.
unload_and_beat() {
  rm -rf "$out/$4_unload"
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" unload "$1" -o "$out/$4_unload" --tolerance "$2" --max-iterations 12
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" run "$3" -o "$out/$4" --progress-interval "$5" \
    --reference "$out/$4_unload/unloaded_mesh.h5"
}

echo "== 4c/6 simulation, biventricular: the biv phantom (CGAL mesh) unloaded from end-diastole, then two beats, LV and RV each with a Windkessel; see biv_unload.yaml, biv_beat.yaml"
t_biv=0
if [[ "${HEART_BIV:-1}" == 1 ]]; then
  t_biv=$SECONDS
  # The phantom is the end-diastolic image: unload it first (biv_unload.yaml), then beat from the
  # unloaded reference, so that the filling ends at the image's volumes.
  unload_and_beat "$here/biv_unload.yaml" 0.05mm "$here/biv_beat.yaml" biv 10s
  t_biv=$((SECONDS - t_biv))
else
  rm -rf "$out/biv" "$out/biv_unload"  # no stale loops from an earlier run in the plots and the report
  echo "skipped (HEART_BIV=0)"
fi

echo "== 5/6 plots and report"
pv_dat() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i == "t") ct = i; if ($i == "lv_volume") cv = i; if ($i == "lv_pressure") cp = i } next }
           { printf "%.6g %.6g %.6g\n", 1e3 * $ct, 1e6 * $cv, 1e-3 * $cp }' "$1" > "$2"
}
pv_dat "$out/sim/globals.csv" "$out/pv.dat"
if [[ "$scar" == 1 ]]; then
  pv_dat "$out/scar/globals.csv" "$out/pv_scar.dat"
  gnuplot -e "data='$out/pv.dat'; scar='$out/pv_scar.dat'; outdir='$out'; period=800" "$here/plots.gp"
else
  gnuplot -e "data='$out/pv.dat'; outdir='$out'; period=800" "$here/plots.gp"
fi
# PV loops in mmHg and the Wiggers diagram (matplotlib, Debian's interpreter: scripts/install-deps).
py=/usr/bin/python3
[[ -x $py ]] || py=python3
"$py" "$here/plot_heart.py" "$out"
"$py" - "$out" "$voxel" "$t_sim" "$scar" > "$out/report.md" <<'PY'
import json, sys
out, voxel, t_sim, scar = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "1"
s = json.load(open(out + "/summary.json"))
c = s["cavities"]["lv"]
g = lambda k, f=1.0: c.get(k, float("nan")) * f
print("# Two LV beats with a circulation, healthy and scarred\n")
print(f"Mesh: `adamss phantom lv` at {voxel} voxels -> `adamss mesh` tet6m, {s['nodes']} nodes, "
      f"{s['elements']} elements. Scene: [lv_beat.yaml](lv_beat.yaml). Integrator {s['integrator']}, "
      f"{s['steps']} steps, {s['newton_iterations']} Newton iterations, simulation {float(s['wall_time_s']):.0f} s wall.\n")
print("| quantity | value |\n|---|---|")
rows = [("end-diastolic volume EDV", f"{g('edv_m3', 1e6):.3f} ml"), ("end-systolic volume ESV", f"{g('esv_m3', 1e6):.3f} ml"),
        ("stroke volume", f"{g('stroke_volume_m3', 1e6):.3f} ml"), ("ejection fraction", f"{100 * g('ejection_fraction'):.1f} %"),
        ("end-diastolic pressure", f"{g('edp_Pa', 1e-3):.2f} kPa"), ("end-systolic pressure", f"{g('esp_Pa', 1e-3):.2f} kPa"),
        ("peak pressure", f"{g('peak_pressure_Pa', 1e-3):.2f} kPa ({g('peak_pressure_Pa', 0.0075006):.0f} mmHg)"),
        ("isovolumic volume drift", f"{100 * g('isovolumic_volume_drift'):.3g} %"),
        ("loop closure after refilling (V_end vs EDV of beat 1)", f"{100 * g('loop_closure'):.3g} %"),
        ("beat-to-beat change of EDV/ESV", f"{100 * g('beat_to_beat_change'):.3g} %"),
        ("fibre stretch min / max", f"{s['fiber_stretch_min']:.3f} / {s['fiber_stretch_max']:.3f}")]
for k in ("mitral_closes_t_s", "aortic_opens_t_s", "aortic_closes_t_s", "mitral_opens_t_s"):
    if k in c: rows.append((k[:-4].replace("_", " ") + " at", f"{1e3 * c[k]:.0f} ms"))
for a, b in rows: print(f"| {a} | {b} |")
beats = c.get("per_beat", [])
if beats:
    mm = 1.0 / 133.322387415
    print("\nPer beat (healthy; pressures in mmHg, dP/dt in mmHg/s):\n\n| beat | EDV (ml) | ESV (ml) | EF | EDP | ESP | peak "
          "| aortic sys/dia | dP/dt max / min | stroke work (mJ) | IVC / ejection / IVR (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|")
    for i, b in enumerate(beats):
        n = lambda k, f=1.0: b.get(k, float("nan")) * f
        print(f"| {i + 1} | {1e6 * b['edv_m3']:.3f} | {1e6 * b['esv_m3']:.3f} | {100 * b['ejection_fraction']:.1f} % | "
              f"{mm * b['edp_Pa']:.1f} | {mm * b['esp_Pa']:.1f} | {mm * b['peak_pressure_Pa']:.1f} | "
              f"{n('aortic_systolic_pressure_Pa', mm):.0f} / {n('aortic_diastolic_pressure_Pa', mm):.0f} | "
              f"{n('dpdt_max_Pa_per_s', mm):.0f} / {n('dpdt_min_Pa_per_s', mm):.0f} | {n('stroke_work_J', 1e3):.1f} | "
              f"{n('isovolumic_contraction_s', 1e3):.0f} / {n('ejection_s', 1e3):.0f} / {n('isovolumic_relaxation_s', 1e3):.0f} |")
print("\n![PV loops in mmHg, with the passive inflation (EDPVR)](pv_loop_mmhg.png)\n\n"
      "![Wiggers diagram: LV, aortic and atrial pressure, LV volume, phases and valve events](wiggers.png)\n\n"
      "Also: [PV loop in kPa](pv_loop.png), [pressure and volume against time](pressure_volume_time.png); "
      "SVG versions beside the PNGs.\n")
import os
if os.path.exists(out + "/espvr.json"):
    e = json.load(open(out + "/espvr.json"))
    print(f"End-systolic pressure-volume relation from {len(e['points'])} beats at three preloads (these two and "
          f"[lv_beat_occlusion.yaml](lv_beat_occlusion.yaml), atrial pressure 0.6 then 0.3 kPa): "
          f"E_es = {e['Ees_mmHg_per_ml']:.1f} mmHg/ml, V_0 = {e['V0_ml']:.2f} ml, r^2 = {e['r2']:.4f} "
          f"([espvr.json](espvr.json)).\n\n![Loops at three preloads with the ESPVR and EDPVR](espvr.png)\n")
rs = json.load(open(out + "/regional_strain.json")) if os.path.exists(out + "/regional_strain.json") else {}
if "healthy" in rs:
    print("Regional fibre strain from end diastole to end systole of the last beat, AHA 17 segments "
          "(anterior = +y, septal = -x of the phantom; [regional_strain.json](regional_strain.json)):\n")
    print("![bull's-eye, healthy](bullseye.png)\n")
if scar:
    z = json.load(open(out + "/scar/summary.json"))
    d = z["cavities"]["lv"]
    ef_h, ef_s = c.get("ejection_fraction", float("nan")), d.get("ejection_fraction", float("nan"))
    print("## Planning scenario: apical-anterior scar\n")
    print("Scar: the wall voxels within 30 deg of the axis (0, 1, -1) from the LV centre (`adamss phantom lv "
          "--scar-out`), carried to the elements as the cell field `scar` (`adamss mesh --cell-field`); there the "
          "material has no active tension and k_ij x10 ([lv_beat_scar.yaml](lv_beat_scar.yaml)). Values of beat 2.\n")
    print("| quantity | healthy | scar |\n|---|---|---|")
    for label, key, f, unit in (("EDV", "edv_m3", 1e6, "ml"), ("ESV", "esv_m3", 1e6, "ml"),
                                ("stroke volume", "stroke_volume_m3", 1e6, "ml"),
                                ("peak pressure", "peak_pressure_Pa", 1e-3, "kPa"),
                                ("end-systolic pressure", "esp_Pa", 1e-3, "kPa")):
        print(f"| {label} | {f * c.get(key, float('nan')):.3f} {unit} | {f * d.get(key, float('nan')):.3f} {unit} |")
    print(f"| ejection fraction | {100 * ef_h:.1f} % | {100 * ef_s:.1f} % |")
    print(f"\nChange in ejection fraction: {100 * (ef_s - ef_h):+.1f} percentage points "
          f"({100 * (ef_s / ef_h - 1):+.1f} % relative).\n")
    print("![PV loops, healthy and scar (mmHg)](pv_loop_scar_mmhg.png)\n")
    if "scar" in rs and "scar_region_percent" in rs["scar"]:
        h, sc = rs["healthy"], rs["scar"]
        print("| fibre strain ED to ES | healthy | scar |\n|---|---|---|")
        print(f"| scar segment | {h.get('scar_region_percent', float('nan')):.1f} % | {sc['scar_region_percent']:.1f} % |")
        print(f"| remote wall | {h.get('remote_percent', float('nan')):.1f} % | {sc['remote_percent']:.1f} % |\n")
        print("![bull's-eye, scar](bullseye_scar.png)\n")
import os
if os.path.exists(out + "/biv/summary.json"):
    b = json.load(open(out + "/biv/summary.json"))
    print(f"\n## Biventricular phantom (`cases/heart/biv_beat.yaml`)\n\n"
          f"{b['nodes']} nodes, {b['elements']} tetrahedra (CGAL); LV and RV each with a Windkessel (the RV's outflow "
          f"is the pulmonary artery: its 'aortic' keys are pulmonary, its 'mitral' keys tricuspid); two beats, "
          f"{b['steps']} steps, simulation {float(b['wall_time_s']):.0f} s wall; wall volume change at most "
          f"{100 * b['total_volume_m3']['max_abs_relative_change']:.2f} %.\n")
    print("| last beat | EDV (ml) | ESV (ml) | SV (ml) | EF | peak (kPa) | outflow sys/dia (kPa) | loop closure |\n"
          "|---|---|---|---|---|---|---|---|")
    for n in ("lv", "rv"):
        cb = b["cavities"].get(n, {})
        nan = float("nan")
        print(f"| {n.upper()} | {1e6 * cb.get('edv_m3', nan):.3f} | {1e6 * cb.get('esv_m3', nan):.3f} | "
              f"{1e6 * cb.get('stroke_volume_m3', nan):.3f} | "
              f"{100 * cb.get('ejection_fraction', nan):.1f} % | {1e-3 * cb.get('peak_pressure_Pa', nan):.2f} | "
              f"{1e-3 * cb.get('aortic_systolic_pressure_Pa', float('nan')):.2f} / "
              f"{1e-3 * cb.get('aortic_diastolic_pressure_Pa', float('nan')):.2f} | {100 * cb.get('loop_closure', float('nan')):.2g} % |")
    if os.path.exists(out + "/biv_unload/unload.json"):
        u = json.load(open(out + "/biv_unload/unload.json"))
        best = u["iterations"][u["best_iteration"]]
        print(f"\nUnloaded reference (`adamss unload`, `biv_unload.yaml`: the phantom taken as the image at "
              f"end-diastole): {len(u['iterations'])} iterations, max distance of the re-filled reference to the "
              f"image {1e3 * u['max_error_m']:.3f} mm.\n")
        print("| cavity | image (ml) | unloaded (ml) | beat's EDV (ml) | EDV vs image |\n|---|---|---|---|---|")
        for n, v in u["imaged_cavity_volumes_m3"].items():
            ref = best["cavities"][n]["reference_m3"]
            edv = b["cavities"].get(n, {}).get("edv_m3", float("nan"))
            print(f"| {n.upper()} | {1e6 * v:.3f} | {1e6 * ref:.3f} | {1e6 * edv:.3f} | {100 * (edv / v - 1):+.2f} % |")
    print("\n![LV and RV loops (mmHg)](pv_loop_biv_mmhg.png)\n")
print("Fields over time (displacement, fibre_stretch, active_tension, J): open [sim/series.pvd](sim/series.pvd) "
      "in ParaView. Every step: [sim/globals.csv](sim/globals.csv); everything: [summary.json](summary.json).")
PY

echo "== 6/6 check against cases/heart/expected.cmake"
if [[ "${HEART_CHECK:-1}" == 1 ]]; then
  cmake -DSUMMARY="$out/summary.json" -DEXPECTED="$here/expected.cmake" -P "$here/check.cmake"
  if [[ "$scar" == 1 ]]; then
    cmake -DHEALTHY="$out/summary.json" -DSCARRED="$out/scar/summary.json" -DEXPECTED="$here/expected.cmake" \
      -P "$here/check_scar.cmake"
  fi
  # check_biv NAME EXPECTED_PREFIX: OUT/NAME's end-diastolic volumes against the image's and both
  # cavities against EXPECTED_PREFIX_lv.cmake / _rv.cmake.
  check_biv() {
    cmake -DUNLOAD="$out/$1_unload/unload.json" -DSUMMARY="$out/$1/summary.json" -P "$here/check_unloaded_edv.cmake"
    for cav in lv rv; do
      cmake -DSUMMARY="$out/$1/summary.json" -DCAVITY=$cav -DEXPECTED="$2_$cav.cmake" -P "$here/check.cmake"
    done
  }
  if [[ "${HEART_BIV:-1}" == 1 ]]; then check_biv biv "$here/biv_expected"; fi
else
  echo "skipped (HEART_CHECK=0)"
fi
cat "$out/report.md"
echo "heart case done in ${SECONDS} s (healthy simulation ${t_sim} s, scarred ${t_scar} s, biventricular ${t_biv} s); results in $out"
