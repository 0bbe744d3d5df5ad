#!/usr/bin/env bash
# The heart case on a patient's label image (issue 20 item 7): `make heart` runs it on the biv-me
# heart of ../shared/anatomy, `make heart HEART_IMAGE=PATH` on any end-diastolic label image in that
# convention. From the label image to two beats:
#   1. the scenes: with an RV label, cases/anatomy/bivme-filling.yaml and bivme-beat.yaml (labels
#      smoothed 0.7 mm, CGAL, rule fibres, pericardium, both ventricles with a Windkessel each);
#      LV only, cases/anatomy/sunnybrook-filling.yaml and sunnybrook-beat.yaml (resampled to
#      1.5 mm, cleaned, CGAL, rule fibres); the image and its labels put in, the beat extended to
#      two periods of 800 ms; the rims of the valve (basal) openings fixed;
#   2. `adamss unload` on the filling scene: the image is at end-diastole, so the reference whose
#      filling to the atrial pressures gives back the image is found first;
#   3. `adamss run` of the two beats from that reference;
#   4. plots (pv_loop_mmhg.png, wiggers.png, with an RV pv_loop_biv_mmhg.png; heart_views.png, a
#      long-axis cut at end diastole and end systole, by render_heart.py) and report.md, with the
#      simulated volumes against the image's: the meshed end-diastolic cavities, their voxel counts
#      and, when the image's folder holds labels_ES_LVbloodpool.nii.gz (the Sunnybrook convention),
#      the end-systolic blood pool.
# Usage: cases/heart/run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR
#   HEART_LABELS names the wall, LV and RV labels (default "solid=1 lv=2 rv=3" when the image has
#   a label 3, else "solid=1 lv=2"); HEART_ES_IMAGE (default IMAGE's
#   folder/labels_ES_LVbloodpool.nii.gz) the end-systolic blood pool; HEART_TWITCH the peak active
#   stress (default: the beat scene's, 60 kPa for the failing Sunnybrook ventricles, the biv-me
#   scene's for biventricular images); HEART_CHECK=0 skips the checks (end-diastolic volumes within
#   3 % of the image's label voxels; LV only: the simulated ESV within 15 % of the end-systolic blood
#   pool); HEART_DRY_RUN=1 writes and checks the scenes (adamss run --check, which meshes the
#   image) and stops. HEART_RANKS: MPI ranks for the two beats (default 2 where the machine has 2
#   or more cores and mpirun starts 2 processes, else 1 process with OMP_NUM_THREADS threads, 2 by
#   default); the unloading runs in one process either way (adamss unload is serial). On this
#   2-core machine the biv-me beats took 222 s on 2 ranks against 321 s in one process with 2
#   threads, the same 1 026 Newton iterations and volumes (2026-12-06).
set -euo pipefail
adamss=${1:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
image=${2:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
out=${3:?usage: run_image.sh ADAMSS_BINARY IMAGE OUTPUT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
anatomy=$here/../anatomy
if [[ ! -f $image ]]; then
  echo "run_image.sh: HEART_IMAGE=$image: no such file (a NIfTI label image: 1 wall, 2 LV blood pool, 3 RV blood pool if any)" >&2
  exit 2
fi
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")
py=/usr/bin/python3
[[ -x $py ]] || py=python3
mkdir -p "$out"
SECONDS=0
"$adamss" info "$image" --json > "$out/image_info.json"
image_labels=$("$py" -c 'import json, sys; print(" ".join(sorted(json.load(open(sys.argv[1]))["labels"], key=int)))' \
  "$out/image_info.json")
default_labels="solid=1 lv=2"
[[ " $image_labels " == *" 3 "* ]] && default_labels="solid=1 lv=2 rv=3"
solid=1 lv=2 rv=""
for kv in ${HEART_LABELS:-$default_labels}; do
  case $kv in
    solid=*) solid=${kv#solid=} ;;
    lv=*) lv=${kv#lv=} ;;
    rv=*) rv=${kv#rv=} ;;
    *)
      echo "run_image.sh: HEART_LABELS entry '$kv' is not solid=N, lv=N or rv=N" >&2
      exit 2
      ;;
  esac
done
for n in "$solid" "$lv" $rv; do
  [[ $n =~ ^[0-9]+$ ]] || { echo "run_image.sh: HEART_LABELS: label '$n' is not a whole number" >&2; exit 2; }
  if [[ " $image_labels " != *" $n "* ]]; then
    echo "run_image.sh: HEART_LABELS names label $n, but $image has no voxel with it (its labels: $image_labels)" >&2
    exit 2
  fi
done
# Labels other than background, wall and cavities are refused: the scenes model the wall and one
# or two cavities, nothing else (an atrium or a vessel label would be meshed as nothing).
other=""
for n in $image_labels; do
  [[ $n == 0 || $n == "$solid" || $n == "$lv" || $n == "$rv" ]] || other="$other $n"
done
if [[ -n $other ]]; then
  echo "run_image.sh: $image has labels$other besides the wall ($solid), the LV ($lv)${rv:+ and the RV ($rv)}:" \
    "HEART_LABELS must name them (solid=N lv=N rv=N) or the image must hold only those" >&2
  exit 2
fi
if [[ -n $rv ]]; then
  kind=biventricular filling_template=$anatomy/bivme-filling.yaml beat_template=$anatomy/bivme-beat.yaml
  tolerance=0.2mm
else
  kind="LV only" filling_template=$anatomy/sunnybrook-filling.yaml beat_template=$anatomy/sunnybrook-beat.yaml
  tolerance=0.1mm
fi
scene_twitch=$(sed -n 's|.*twitch: {peak: \([0-9.]*\) kPa.*|\1|p' "$beat_template")
es_image=${HEART_ES_IMAGE:-$(dirname "$image")/labels_ES_LVbloodpool.nii.gz}
twitch=${HEART_TWITCH:-${scene_twitch}kPa}
twitch_value=${twitch%kPa}
[[ $twitch_value =~ ^[0-9]+([.][0-9]+)?$ && $twitch == *kPa ]] || {
  echo "run_image.sh: HEART_TWITCH=$twitch: give the peak active stress in kPa, e.g. 60kPa" >&2
  exit 2
}
threads=${OMP_NUM_THREADS:-2}
mpirun_env=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1)  # Open MPI refuses root otherwise
ranks=${HEART_RANKS:-auto}  # auto: chosen before the beats (2 where they can start)
if [[ $ranks != auto ]]; then
  if [[ ! $ranks =~ ^[1-9][0-9]*$ ]]; then
    echo "run_image.sh: HEART_RANKS=$ranks: give a number of MPI ranks (1 runs one process with threads)" >&2
    exit 2
  fi
  if ((ranks > 1)) && ! command -v mpirun > /dev/null; then
    echo "run_image.sh: HEART_RANKS=$ranks needs mpirun, which is not on PATH" >&2
    exit 2
  fi
fi

echo "== 1/4 image and scenes: $image ($kind: wall label $solid, LV label $lv${rv:+, RV label $rv})"
"$adamss" info "$image"
# The recipe's keys of the two template scenes, with this image and its labels.
scene() {
  sed -e "s|^  image: .*|  image: $image|" -e "s|^  solid: 1$|  solid: $solid|" \
    -e "s|^  cavities: {lv: 2}$|  cavities: {lv: $lv}|" -e "s|^  cavities: {lv: 2, rv: 3}$|  cavities: {lv: $lv, rv: $rv}|" \
    -e "s|^    labels: \[1\]$|    labels: [$solid]|" "$1"
}
scene "$filling_template" | sed -e "s|^name: .*|name: image-filling|" > "$out/filling.yaml"
# Two periods: each circulation gets period 800 ms (the Sunnybrook beat has none; the biv-me one
# has it already) and the run ends at 1.6 s.
scene "$beat_template" |
  sed -e "s|^name: .*|name: image-beat|" -e "s|peak: $scene_twitch kPa|peak: $twitch_value kPa|" \
    -e "/^        period: 800 ms$/d" \
    -e "s|^        contraction_onset: 100 ms$|        contraction_onset: 100 ms\n        period: 800 ms|" \
    -e "s|^run: {t_end: 800 ms}$|run: {t_end: 1600 ms}|" > "$out/beat.yaml"
cavity_line="  cavities: {lv: $lv}"
[[ -n $rv ]] && cavity_line="  cavities: {lv: $lv, rv: $rv}"
for f in filling beat; do
  if ! grep -qF "image: $image" "$out/$f.yaml" || ! grep -q "^    labels: \[$solid\]$" "$out/$f.yaml" ||
    ! grep -qxF "$cavity_line" "$out/$f.yaml"; then
    echo "run_image.sh: $f.yaml: the image or its labels were not put in" >&2
    exit 1
  fi
done
periods=$(grep -c "^        period: 800 ms$" "$out/beat.yaml" || true)
if ! grep -q "^run: {t_end: 1600 ms}$" "$out/beat.yaml" || [[ $periods != "$(grep -c "^        contraction_onset:" "$out/beat.yaml")" ]] ||
  ! grep -q "peak: $twitch_value kPa" "$out/beat.yaml"; then
  echo "run_image.sh: beat.yaml: the two-beat settings were not put in" >&2
  exit 1
fi
if [[ ${HEART_DRY_RUN:-0} == 1 ]]; then
  # Scenes only, validated (and the image meshed) by adamss run --check; nothing is simulated.
  "$adamss" run "$out/filling.yaml" --check
  "$adamss" run "$out/beat.yaml" --check
  echo "HEART_DRY_RUN=1: $kind scenes written and checked in $out"
  exit 0
fi

echo "== 2/4 unloaded reference: adamss unload filling.yaml (the image is at end-diastole, loaded by the atrial pressures)"
t_unload=$SECONDS
rm -rf "$out/unload"
OMP_NUM_THREADS=$threads "$adamss" unload "$out/filling.yaml" -o "$out/unload" --tolerance "$tolerance" --max-iterations 20
t_unload=$((SECONDS - t_unload))

echo "== 3/4 two beats from the unloaded reference (twitch $twitch_value kPa), see beat.yaml"
t_sim=$SECONDS
if [[ $ranks == auto ]]; then  # 2 ranks where they can start (tried with a trivial program)
  ranks=1
  if (($(nproc) >= 2)) && command -v mpirun > /dev/null && "${mpirun_env[@]}" mpirun -np 2 true > /dev/null 2>&1; then
    ranks=2
  fi
fi
beat_args=(run "$out/beat.yaml" -o "$out/sim" --reference "$out/unload/unloaded_mesh.h5" --progress-interval 20s)
if ((ranks > 1)); then
  echo "   on $ranks MPI ranks (HEART_RANKS=1: one process with threads)"
  "${mpirun_env[@]}" mpirun -np "$ranks" "$adamss" "${beat_args[@]}"
else
  OMP_NUM_THREADS=$threads "$adamss" "${beat_args[@]}"
fi
t_sim=$((SECONDS - t_sim))
cp "$out/sim/summary.json" "$out/summary.json"

echo "== 4/4 plots and report"
es_json=""
if [[ -z $rv && -f $es_image ]]; then
  "$adamss" info "$es_image" --json > "$out/es_image_info.json"
  es_json=$out/es_image_info.json
fi
"$py" "$here/plot_heart.py" "$out" "$out/sim" --no-regional
# The picture is not worth losing the report for: a failure is reported and the report still written.
rm -f "$out/heart_views.png" "$out/heart_views.json"
"$py" "$here/render_heart.py" "$out/sim" "$out/heart_views.png" ||
  echo "run_image.sh: warning: render_heart.py drew no heart_views.png (its message above); the report follows without it" >&2
"$py" "$here/image_report.py" "$out" "$image" "$lv" "$rv" "$es_image" "$es_json" "$t_unload" "$t_sim" \
  "${HEART_CHECK:-1}"
echo "heart case on $image done in ${SECONDS} s: $out/report.md"
