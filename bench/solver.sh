#!/usr/bin/env bash
# The implicit solver's time split (issue 19): for each benchmark scene, one thread, BENCH_REPEAT
# runs of `adamss run` (default 3; 1 with BENCH_QUICK=1), the fastest kept. Per run PETSc's
# -log_view gives the time of the numerical LU factorisations (MatLUFactorNum, their count is the
# number of Jacobians factorised) and of the triangular solves (KSPSolve); everything else in the
# run -- residuals, Jacobian assembly, elimination, output -- is the remainder of PETSc's total
# ("assembly and residuals" below; start-up before PETSc is initialised is outside PETSc's total
# and counted in wall_s only).
# Writes OUT_JSON (default bench/results/solver.json) and prints one line per scene.
# Usage: bench/solver.sh ADAMSS_BINARY [OUT_JSON]
set -euo pipefail
adamss=${1:?usage: solver.sh ADAMSS_BINARY [OUT_JSON]}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
out=${2:-$here/results/solver.json}
repeat=${BENCH_REPEAT:-$([[ ${BENCH_QUICK:-0} == 1 ]] && echo 1 || echo 3)}
scenes=${BENCH_SOLVER_SCENES:-"cases/benchmarks/land-p1.yaml cases/benchmarks/land-p1-half.yaml cases/benchmarks/land-p1-fast.yaml cases/benchmarks/land-p2.yaml"}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# "name value" of a -log_view event line: its max time (column 4) and count (column 2).
event() { awk -v e="$1" '$1 == e {print $2, $4; found = 1} END {if (!found) print 0, 0}' "$2"; }

rows=""
for scene in $scenes; do
  name=$(basename "$scene" .yaml)
  best=""
  for ((r = 0; r < repeat; ++r)); do
    start=$(date +%s.%N)
    OMP_NUM_THREADS=1 PETSC_OPTIONS="-log_view :$tmp/log.txt" "$adamss" run "$root/$scene" -o "$tmp/out" -q
    end=$(date +%s.%N)
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.3f", b - a}')
    if [[ -z $best ]] || awk -v w="$wall" -v b="$best" 'BEGIN {exit !(w < b)}'; then
      best=$wall
      cp "$tmp/log.txt" "$tmp/best.txt"
      cp "$tmp/out/summary.json" "$tmp/best.json"
    fi
  done
  read -r nfact tfact < <(event MatLUFactorNum "$tmp/best.txt")
  read -r nsolve tsolve < <(event KSPSolve "$tmp/best.txt")
  total=$(awk '/^Time \(sec\):/ {print $3}' "$tmp/best.txt")
  rest=$(awk -v t="$total" -v f="$tfact" -v s="$tsolve" 'BEGIN {printf "%.3f", t - f - s}')
  newton=$(sed -n 's/.*"newton_iterations": *\([0-9]*\).*/\1/p' "$tmp/best.json" | head -1)
  linear=$(sed -n 's/.*"linear_iterations": *\([0-9]*\).*/\1/p' "$tmp/best.json" | head -1)
  steps=$(sed -n 's/.*"steps": *\([0-9]*\).*/\1/p' "$tmp/best.json" | head -1)
  per_fact=$(awk -v n="$nfact" -v t="$tfact" 'BEGIN {printf "%.4f", (n > 0) ? t / n : 0}')
  echo "$name: wall $best s (fastest of $repeat), $steps load steps, $newton Newton, $linear linear;" \
    "factorisation $tfact s ($nfact x $per_fact s), solves $tsolve s ($nsolve), assembly and residuals $rest s"
  rows="$rows${rows:+,}
    {\"scene\": \"$scene\", \"wall_s\": $best, \"repeats\": $repeat, \"steps\": $steps, \"newton_iterations\": $newton,
     \"linear_iterations\": $linear, \"factorisations\": $nfact, \"factorisation_s\": $tfact,
     \"solves\": $nsolve, \"solve_s\": $tsolve, \"assembly_and_residuals_s\": $rest, \"petsc_total_s\": $total}"
done
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)
cat > "$out" <<JSON
{
  "what": "adamss run, one thread: time split from PETSc -log_view (bench/solver.sh)",
  "cpu": "$cpu",
  "runs": [$rows
  ]
}
JSON
echo "wrote $out"
