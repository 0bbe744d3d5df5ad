#!/usr/bin/env bash
# Speed against error (issue 9, parts 4 and 6): runs every (problem, model, topology, level,
# solver) of plan.sh once, one adamss process at a time on one thread, then writes
# RESULTS_DIR/pareto.json, pareto.md and pareto_<problem>.png (report.sh).
# Usage: bench/pareto/run.sh ADAMSS_BINARY RESULTS_DIR      (PARETO_QUICK=1: the < 3 min sweep)
# Levels of one (problem, model, topology, solver) run coarse to fine; after a timeout
# the finer levels are not run (they would be slower still) and are recorded as "skipped".
set -euo pipefail
adamss=$(realpath "${1:?usage: run.sh ADAMSS_BINARY RESULTS_DIR}")
results=${2:?usage: run.sh ADAMSS_BINARY RESULTS_DIR}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$results"
results=$(realpath "$results")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export ADAMSS_CACHE_DIR=$work/cache
if [[ ${PARETO_QUICK:-0} == 1 ]]; then
  cap_static=20 cap_implicit=10 cap_explicit=4
else
  cap_static=90 cap_implicit=40 cap_explicit=20
fi
# Springs for the Guccione laws, fitted by `adamss fit` (default 20 % strain range, powers 1, 3).
for p in 1 2; do
  "$adamss" fit --law "guccione_land_problem$p" | sed -n '/^Scene terms:/,$p' | tail -n +2 > "$work/p$p.terms"
done
rows=$results/rows.tsv
printf 'problem\tmodel\ttopology\tlevel\tsolver\tstatus\treason\twall_s\tprocess_s\tsteps\telements\tnodes\tqoi\tqoi2\n' > "$rows"
start=$(date +%s)
while read -r problem model topo levels; do
  # PARETO_MODELS="m1 m2": only these models (e.g. to add the new elements to a sweep).
  if [[ -n ${PARETO_MODELS:-} && " $PARETO_MODELS " != *" $model "* ]]; then continue; fi
  for solver in static implicit explicit; do
    # The augmented Lagrangian updates its multipliers, and the continuation raises its penalty,
    # between static solves only.
    if [[ $model == fem_q1p0 || $model == fem_staged || $model == fem_nodal || $model == fem_p2p* || $model == fem_q2p1 ]] && [[ $solver != static ]]; then continue; fi
    cap_var=cap_$solver
    skip=""
    for level in $levels; do
      if [[ -n $skip ]]; then
        printf '%s\t%s\t%s\t%s\t%s\tskipped\t%s\tnull\tnull\tnull\tnull\tnull\tnull\tnull\n' \
          "$problem" "$model" "$topo" "$level" "$solver" "$skip" >> "$rows"
        continue
      fi
      row=$("$here/run_one.sh" "$adamss" "$work" "$problem" "$model" "$topo" "$level" "$solver" "${!cap_var}" "$work")
      echo "$row" >> "$rows"
      echo "[$(($(date +%s) - start)) s] $row" | cut -f1-9,13 >&2
      status=$(cut -f6 <<< "$row")
      if [[ $status == timeout ]]; then skip="coarser_level_timeout"; fi
    done
  done
done < <("$here/plan.sh")
echo "sweep: $(($(date +%s) - start)) s" >&2
"$here/report.sh" "$rows" "$results" "$here/not_applicable.tsv"
