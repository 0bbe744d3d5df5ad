#!/usr/bin/env bash
# Runs one sweep configuration and prints one tab-separated row:
#   problem model topology level solver status reason solver_wall_s process_wall_s steps elements nodes qoi qoi2
# Usage: run_one.sh ADAMSS WORKDIR PROBLEM MODEL TOPOLOGY LEVEL SOLVER CAP_SECONDS FITDIR
# Explicit runs get dt = 0.5 x the loader's critical step estimate (read from `adamss run --check`).
# A run killed by the wall-time cap gets status "timeout"; a run without summary.json "failed".
set -uo pipefail
adamss=$1 work=$2 problem=$3 model=$4 topo=$5 level=$6 solver=$7 cap=$8 fitdir=$9
here=$(cd "$(dirname "$0")" && pwd)
id="$problem-$model-$topo-$level-$solver"
scene="$work/$id.yaml" out="$work/$id"
mkdir -p "$work"; rm -rf "$out"
# The placeholder step of the --check scene only has to pass the scene check's bound of 10^9 steps
# (t_end is at most 60 s here; check_dt: false keeps it from being compared with the critical step).
dt=1e-6
if [[ $solver == explicit ]]; then
  "$here/scene.sh" "$problem" "$model" "$topo" "$level" "$solver" "$dt" "$fitdir" > "$scene"
  hc=$("$adamss" run --check "$scene" 2>&1 | sed -n 's/.*critical step estimate \([0-9.e+-]*\) *\(s\|ms\|us\).*/\1 \2/p' | head -1)
  dt=$(awk -v v="${hc% *}" -v u="${hc#* }" 'BEGIN{f = (u == "ms") ? 1e-3 : (u == "us") ? 1e-6 : 1; printf "%.4g", 0.5 * v * f}')
fi
"$here/scene.sh" "$problem" "$model" "$topo" "$level" "$solver" "$dt" "$fitdir" > "$scene"
t0=$(date +%s.%N)
OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive timeout -k 10 "$cap" "$adamss" run "$scene" -o "$out" -q > "$out.log" 2>&1
rc=$?
t1=$(date +%s.%N)
proc=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b - a}')
if [[ -f $out/summary.json ]]; then
  vals=$(cmake -DSUMMARY="$out/summary.json" -DPROBLEM="$problem" -P "$here/extract.cmake")
else
  vals=$(printf 'failed\texit_%s\tnull\tnull\tnull\tnull\tnull\tnull' "$rc")
fi
if [[ $rc == 124 || $rc == 137 ]]; then  # timeout's exit codes (SIGTERM sent / SIGKILL needed)
  vals=$(printf '%s' "$vals" | awk -F'\t' -v OFS='\t' -v cap="$cap" '{$1 = "timeout"; $2 = "wall_cap_" cap "s"; print}')
fi
IFS=$'\t' read -r status reason wall steps elements nodes qoi qoi2 <<< "$vals"
printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' \
  "$problem" "$model" "$topo" "$level" "$solver" "$status" "$reason" "$wall" "$proc" "$steps" "$elements" "$nodes" "$qoi" "$qoi2"
