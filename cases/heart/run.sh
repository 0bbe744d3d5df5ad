#!/usr/bin/env bash
# The heart case, end to end: image -> mesh -> one simulated beat with a circulation -> plots,
# report and check.
# Usage: cases/heart/run.sh ADAMSS_BINARY OUTPUT_DIR
#   HEART_VOXEL (default 2.5mm; 1.25mm does not yet finish: the refilling after the beat stalls) sets the voxel size (the base plane z = 5 mm must be a whole
#   number of voxels: 0.5, 1, 1.25, 2.5 mm); HEART_CHECK=0 skips the physiology check.
# Writes OUTPUT_DIR/{summary.json, pv_loop.png, pressure_volume_time.png, report.md} and the
# simulation in OUTPUT_DIR/sim (series.pvd + frames/*.vtu, globals.csv).
set -euo pipefail
adamss=${1:?usage: run.sh ADAMSS_BINARY OUTPUT_DIR}
out=${2:?usage: run.sh ADAMSS_BINARY OUTPUT_DIR}
voxel=${HEART_VOXEL:-2.5mm}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
SECONDS=0

echo "== 1/5 phantom: Land 2015 LV truncated ellipsoid, $voxel voxels, helix +60/-60 deg"
"$adamss" phantom lv --voxel-size "$voxel" -o "$out/lv.nii.gz" \
  --fiber-out "$out/lv_fiber.nii.gz" --sheet-out "$out/lv_sheet.nii.gz" --helix-endo 60 --helix-epi -60

echo "== 2/5 mesh: tet6m, phantom fibres, closed LV cavity (label 2) with its lid, base plane tag"
"$adamss" mesh "$out/lv.nii.gz" --solid 1 --topology tet6m \
  --fiber "$out/lv_fiber.nii.gz" --sheet "$out/lv_sheet.nii.gz" \
  --cavity lv=2 --tag-plane base=z:5mm -o "$out/lv.h5"
"$adamss" info "$out/lv.h5" --json > "$out/mesh_info.json"
"$adamss" info "$out/lv.h5"

echo "== 3/5 simulation: one beat (filling, IVC, Windkessel ejection, IVR, refilling), see lv_beat.yaml"
cp "$here/lv_beat.yaml" "$out/lv_beat.yaml"
t_sim=$SECONDS
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$adamss" run "$out/lv_beat.yaml" -o "$out/sim" -q
t_sim=$((SECONDS - t_sim))
cp "$out/sim/summary.json" "$out/summary.json"

echo "== 4/5 plots and report"
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i == "t") ct = i; if ($i == "lv_volume") cv = i; if ($i == "lv_pressure") cp = i } next }
         { printf "%.6g %.6g %.6g\n", 1e3 * $ct, 1e6 * $cv, 1e-3 * $cp }' "$out/sim/globals.csv" > "$out/pv.dat"
gnuplot -e "data='$out/pv.dat'; outdir='$out'" "$here/plots.gp"
python3 - "$out" "$voxel" "$t_sim" > "$out/report.md" <<'PY'
import json, sys
out, voxel, t_sim = sys.argv[1], sys.argv[2], sys.argv[3]
s = json.load(open(out + "/summary.json"))
c = s["cavities"][0]
g = lambda k, f=1.0: c.get(k, float("nan")) * f
print("# LV beat with a circulation\n")
print(f"Mesh: `adamss phantom lv` at {voxel} voxels -> `adamss mesh` tet6m, {s['nodes']} nodes, "
      f"{s['elements']} elements. Scene: [lv_beat.yaml](lv_beat.yaml). Integrator {s['integrator']}, "
      f"{s['steps']} steps, {s['newton_iterations']} Newton iterations, simulation {float(s['wall_time_s']):.0f} s wall.\n")
print("| quantity | value |\n|---|---|")
rows = [("end-diastolic volume EDV", f"{g('edv_m3', 1e6):.3f} ml"), ("end-systolic volume ESV", f"{g('esv_m3', 1e6):.3f} ml"),
        ("stroke volume", f"{g('stroke_volume_m3', 1e6):.3f} ml"), ("ejection fraction", f"{100 * g('ejection_fraction'):.1f} %"),
        ("end-diastolic pressure", f"{g('edp_Pa', 1e-3):.2f} kPa"), ("end-systolic pressure", f"{g('esp_Pa', 1e-3):.2f} kPa"),
        ("peak pressure", f"{g('peak_pressure_Pa', 1e-3):.2f} kPa ({g('peak_pressure_Pa', 0.0075006):.0f} mmHg)"),
        ("isovolumic volume drift", f"{100 * g('isovolumic_volume_drift'):.3g} %"),
        ("loop closure after refilling", f"{100 * g('loop_closure'):.3g} %"),
        ("fibre stretch min / max", f"{s['fiber_stretch_min']:.3f} / {s['fiber_stretch_max']:.3f}")]
for k in ("mitral_closes_t_s", "aortic_opens_t_s", "aortic_closes_t_s", "mitral_opens_t_s"):
    if k in c: rows.append((k[:-4].replace("_", " ") + " at", f"{1e3 * c[k]:.0f} ms"))
for a, b in rows: print(f"| {a} | {b} |")
print("\n![PV loop](pv_loop.png)\n\n![pressure and volume](pressure_volume_time.png)\n")
print("Fields over time (displacement, fibre_stretch, active_tension, J): open [sim/series.pvd](sim/series.pvd) "
      "in ParaView. Every step: [sim/globals.csv](sim/globals.csv); everything: [summary.json](summary.json).")
PY

echo "== 5/5 check against cases/heart/expected.cmake"
if [[ "${HEART_CHECK:-1}" == 1 ]]; then
  cmake -DSUMMARY="$out/summary.json" -DEXPECTED="$here/expected.cmake" -P "$here/check.cmake"
else
  echo "skipped (HEART_CHECK=0)"
fi
cat "$out/report.md"
echo "heart case done in ${SECONDS} s (simulation ${t_sim} s); results in $out"
