#!/usr/bin/env bash
# The heart case on a patient's LV label image (issue 20 item 7): `make heart HEART_IMAGE=PATH`
# runs this instead of the phantom case. From the end-diastolic label image to two beats:
#   1. the scenes: cases/anatomy/sunnybrook-filling.yaml and sunnybrook-beat.yaml with the image
#      and its labels put in (the mesh recipe resamples to 1.5 mm, cleans, meshes with CGAL and
#      puts rule-based fibres on it; the rims of the basal openings are fixed), the beat extended to
#      two periods of 800 ms;
#   2. `adamss unload` on the filling scene: the image is at end-diastole, so the reference whose
#      filling to the atrial pressure (1 kPa) gives back the image is found first;
#   3. `adamss run` of the two beats from that reference;
#   4. plots (pv_loop_mmhg.png, wiggers.png) and report.md, with the simulated volumes against the
#      image's: the meshed end-diastolic cavity and, when the image's folder holds
#      labels_ES_LVbloodpool.nii.gz (the Sunnybrook convention), its end-systolic blood pool.
# Usage: cases/heart/run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR
#   HEART_LABELS (default "solid=1 lv=2", the Sunnybrook labels) names the wall and LV labels;
#   HEART_ES_IMAGE (default IMAGE's folder/labels_ES_LVbloodpool.nii.gz) the end-systolic blood
#   pool; HEART_TWITCH (default 60kPa, the failing ventricle of sunnybrook-beat.yaml) the peak
#   active stress; HEART_CHECK=0 skips the check that the simulated ESV is within 15 % of the
#   end-systolic blood pool (issue 20); HEART_DRY_RUN=1 writes and checks the scenes (adamss run
#   --check, which meshes the image) and stops. Only LV images: a label image with an RV cavity is refused
#   (the biv-me heart unloads, but its beat is not robust yet: cases/anatomy/README.md).
set -euo pipefail
adamss=${1:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
image=${2:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
out=${3:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
anatomy=$here/../anatomy
if [[ ! -f $image ]]; then
  echo "run_image.sh: HEART_IMAGE=$image: no such file (a NIfTI label image: 1 wall, 2 LV blood pool)" >&2
  exit 2
fi
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")
solid=1 lv=2
for kv in ${HEART_LABELS:-solid=1 lv=2}; do
  case $kv in
    solid=*) solid=${kv#solid=} ;;
    lv=*) lv=${kv#lv=} ;;
    rv=*)
      echo "run_image.sh: HEART_LABELS has an RV ($kv): only LV images run end to end today (the biv-me" \
        "heart's beat is not robust yet: cases/anatomy/README.md, bivme-beat.yaml)" >&2
      exit 2
      ;;
    *)
      echo "run_image.sh: HEART_LABELS entry '$kv' is not solid=N or lv=N" >&2
      exit 2
      ;;
  esac
done
for n in "$solid" "$lv"; do
  [[ $n =~ ^[0-9]+$ ]] || { echo "run_image.sh: HEART_LABELS: label '$n' is not a whole number" >&2; exit 2; }
done
es_image=${HEART_ES_IMAGE:-$(dirname "$image")/labels_ES_LVbloodpool.nii.gz}
twitch=${HEART_TWITCH:-60kPa}
twitch_value=${twitch%kPa}
[[ $twitch_value =~ ^[0-9]+([.][0-9]+)?$ && $twitch == *kPa ]] || {
  echo "run_image.sh: HEART_TWITCH=$twitch: give the peak active stress in kPa, e.g. 60kPa" >&2
  exit 2
}
threads=${OMP_NUM_THREADS:-2}
py=/usr/bin/python3
[[ -x $py ]] || py=python3
mkdir -p "$out"
SECONDS=0

echo "== 1/4 image and scenes: $image (wall label $solid, LV label $lv)"
"$adamss" info "$image" --json > "$out/image_info.json"
"$adamss" info "$image"
# Labels other than background, wall and LV (an RV blood pool, say) are refused: the scenes model
# one cavity, and the biv-me beat is not robust yet (cases/anatomy/README.md).
other=$("$py" -c 'import json, sys
d = json.load(open(sys.argv[1]))
print(" ".join(k for k in sorted(d["labels"], key=int) if k not in ("0", sys.argv[2], sys.argv[3])))' \
  "$out/image_info.json" "$solid" "$lv")
if [[ -n $other ]]; then
  echo "run_image.sh: $image has labels $other besides the wall ($solid) and the LV ($lv): only LV images run" \
    "end to end today (an RV needs the biventricular scenes; the biv-me beat is not robust yet: cases/anatomy/bivme-beat.yaml)" >&2
  exit 2
fi
# The recipe's keys of the two Sunnybrook scenes, with this image and its labels.
scene() {
  sed -e "s|^  image: .*|  image: $image|" -e "s|^  solid: 1$|  solid: $solid|" -e "s|^  cavities: {lv: 2}$|  cavities: {lv: $lv}|" \
    -e "s|^    labels: \[1\]$|    labels: [$solid]|" "$1"
}
scene "$anatomy/sunnybrook-filling.yaml" | sed -e "s|^name: .*|name: image-filling|" > "$out/filling.yaml"
scene "$anatomy/sunnybrook-beat.yaml" |
  sed -e "s|^name: .*|name: image-beat|" -e "s|peak: 60 kPa|peak: $twitch_value kPa|" \
    -e "s|^        contraction_onset: 100 ms$|        contraction_onset: 100 ms\n        period: 800 ms|" \
    -e "s|^run: {t_end: 800 ms}$|run: {t_end: 1600 ms}|" > "$out/beat.yaml"
for f in filling beat; do
  if ! grep -qF "image: $image" "$out/$f.yaml" || ! grep -q "^    labels: \[$solid\]$" "$out/$f.yaml"; then
    echo "run_image.sh: $f.yaml: the image or its labels were not put in" >&2
    exit 1
  fi
done
if ! grep -q "^run: {t_end: 1600 ms}$" "$out/beat.yaml" || ! grep -q "^        period: 800 ms$" "$out/beat.yaml" ||
  ! grep -q "peak: $twitch_value kPa" "$out/beat.yaml"; then
  echo "run_image.sh: beat.yaml: the two-beat settings were not put in" >&2
  exit 1
fi
if [[ ${HEART_DRY_RUN:-0} == 1 ]]; then
  # Scenes only, validated (and the image meshed) by adamss run --check; nothing is simulated.
  "$adamss" run "$out/filling.yaml" --check
  "$adamss" run "$out/beat.yaml" --check
  echo "HEART_DRY_RUN=1: scenes written and checked in $out"
  exit 0
fi

echo "== 2/4 unloaded reference: adamss unload filling.yaml (the image is at end-diastole, 1 kPa)"
t_unload=$SECONDS
rm -rf "$out/unload"
OMP_NUM_THREADS=$threads "$adamss" unload "$out/filling.yaml" -o "$out/unload" --tolerance 0.1mm --max-iterations 20
t_unload=$((SECONDS - t_unload))

echo "== 3/4 two beats from the unloaded reference (twitch $twitch_value kPa), see beat.yaml"
t_sim=$SECONDS
OMP_NUM_THREADS=$threads "$adamss" run "$out/beat.yaml" -o "$out/sim" --reference "$out/unload/unloaded_mesh.h5" \
  --progress-interval 10s
t_sim=$((SECONDS - t_sim))
cp "$out/sim/summary.json" "$out/summary.json"

echo "== 4/4 plots and report"
es_json=""
if [[ -f $es_image ]]; then
  "$adamss" info "$es_image" --json > "$out/es_image_info.json"
  es_json=$out/es_image_info.json
fi
"$py" "$here/plot_heart.py" "$out" "$out/sim" --no-regional
"$py" - "$out" "$image" "$lv" "$es_image" "$es_json" "$t_unload" "$t_sim" "${HEART_CHECK:-1}" <<'PY'
import json, sys
out, image, lv, es_image, es_json, t_unload, t_sim, check = sys.argv[1:9]
s = json.load(open(out + "/summary.json"))
c = s["cavities"]["lv"]
u = json.load(open(out + "/unload/unload.json"))
info = json.load(open(out + "/image_info.json"))
nan = float("nan")
ml = lambda v: 1e6 * v
ed_voxels = info["labels"].get(lv, 0) * info["voxel_volume_m3"]
meshed = u["imaged_cavity_volumes_m3"]["lv"]
best = u["iterations"][u["best_iteration"]]
edv, esv, ef = c.get("edv_m3", nan), c.get("esv_m3", nan), c.get("ejection_fraction", nan)
lines = ["# Two beats of a patient's LV from its label image\n",
         f"Image: `{image}` (LV label {lv}). Mesh: {s['nodes']} nodes, {s['elements']} tetrahedra (the recipe of "
         "[beat.yaml](beat.yaml): resampled to 1.5 mm, cleaned, CGAL, rule-based fibres). Unloading "
         f"{len(u['iterations'])} iterations ({t_unload} s), max distance of the re-filled reference to the image "
         f"{1e3 * u['max_error_m']:.3f} mm; two beats {s['steps']} steps, {s['newton_iterations']} Newton iterations "
         f"({t_sim} s). Wall volume change at most {100 * s['total_volume_m3']['max_abs_relative_change']:.2f} %.\n",
         "| | simulated (last beat) | image |", "|---|---|---|",
         f"| EDV | {ml(edv):.1f} ml | {ml(meshed):.1f} ml (the meshed ED cavity; {ml(ed_voxels):.1f} ml by voxel count) |"]
result = {"edv_m3": edv, "esv_m3": esv, "ejection_fraction": ef, "image_ed_cavity_m3": meshed,
          "image_ed_voxels_m3": ed_voxels, "unloaded_cavity_m3": best["cavities"]["lv"]["reference_m3"]}
failed = False
if es_json:
    es = json.load(open(es_json))
    es_vox = sum(n for k, n in es["labels"].items() if k != "0") * es["voxel_volume_m3"]
    scaled = es_vox * meshed / ed_voxels if ed_voxels > 0 else nan
    ef_img = 1.0 - es_vox / ed_voxels if ed_voxels > 0 else nan
    err = esv / es_vox - 1.0
    lines.append(f"| ESV | {ml(esv):.1f} ml | {ml(es_vox):.1f} ml by voxel count of `{es_image}` "
                 f"({ml(scaled):.1f} ml scaled to the meshed ED cavity) |")
    lines.append(f"| EF | {100 * ef:.1f} % | {100 * ef_img:.1f} % (voxel counts) |")
    lines.append(f"\nSimulated ESV against the image's end-systolic blood pool: {100 * err:+.1f} % by voxel count, "
                 f"{100 * (esv / scaled - 1):+.1f} % against the scaled value (issue 20 asks within 15 %).")
    result.update({"image_es_voxels_m3": es_vox, "esv_error_vs_image": err})
    failed = check != "0" and not abs(err) <= 0.15
else:
    lines.append(f"| ESV | {ml(esv):.1f} ml | (no end-systolic image: {es_image}) |")
    lines.append(f"| EF | {100 * ef:.1f} % | |")
lines.append(f"\nPeak LV pressure {1e-3 * c.get('peak_pressure_Pa', nan):.2f} kPa "
             f"({c.get('peak_pressure_Pa', nan) / 133.322:.0f} mmHg); loop closure {100 * c.get('loop_closure', nan):.2g} %; "
             f"beat-to-beat change {100 * c.get('beat_to_beat_change', nan):.2g} %.\n")
lines.append("![PV loops in mmHg](pv_loop_mmhg.png)\n\n![Wiggers diagram](wiggers.png)\n\n"
             "Fields over time: [sim/series.pvd](sim/series.pvd) in ParaView; every step: [sim/globals.csv](sim/globals.csv).")
open(out + "/report.md", "w").write("\n".join(lines) + "\n")
json.dump(result, open(out + "/image_comparison.json", "w"), indent=2)
print("\n".join(lines[2:8]))
if failed:
    sys.exit(f"run_image.sh: the simulated ESV is {100 * err:+.1f} % off the image's end-systolic blood pool "
             "(more than 15 %); HEART_TWITCH sets the contractility")
PY
echo "heart case on $image done in ${SECONDS} s: $out/report.md"
