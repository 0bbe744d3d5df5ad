#!/usr/bin/env bash
# SIGTERM to one of 2 ranks in the middle of a run (docs/parallel.md): the ranks agree to stop at the
# same point, both exit 130, rank 0 writes checkpoint.h5 and summary.json ("interrupted"), and the
# checkpoint resumes on one rank to the end.
#   tests/mpi/sigterm.sh ADAMSS MPIEXEC SCENE OUT CACHE
set -euo pipefail
adamss=$1 mpiexec=$2 scene=$3 out=$4 cache=$5
rm -rf "$out"
mkdir -p "$out"
"$mpiexec" --oversubscribe -np 2 "$adamss" run "$scene" -o "$out/run" --cache "$cache" -q &
pid=$!
# Signal once two load steps are logged (header + 2 rows), so the stop lands inside the run.
for _ in $(seq 1 1500); do  # up to 5 min: a fresh cache meshes the image first
  if [[ -f "$out/run/globals.csv" ]] && (($(wc -l < "$out/run/globals.csv") >= 3)); then break; fi
  sleep 0.2
done
# The signal goes to one rank only (the last adamss child of mpirun): the other learns of it when
# the ranks agree at the next poll (solver/core/stop_flag.hpp), and both stop at the same point.
rank=$(pgrep -P "$pid" -x adamss | tail -n 1)
[[ -n $rank ]] || { echo "FAIL: no adamss rank under mpirun $pid" >&2; exit 1; }
kill -TERM "$rank"
rc=0
wait "$pid" || rc=$?
echo "mpirun exited with $rc after SIGTERM to rank process $rank"
[[ $rc == 130 ]] || { echo "FAIL: expected exit status 130 (interrupted) from every rank" >&2; exit 1; }
grep -q '"status": "interrupted"' "$out/run/summary.json" || {
  echo "FAIL: summary.json does not say interrupted:" >&2
  head -c 400 "$out/run/summary.json" >&2
  exit 1
}
[[ -f "$out/run/checkpoint.h5" ]] || { echo "FAIL: no checkpoint.h5" >&2; exit 1; }
"$adamss" run "$scene" --resume "$out/run/checkpoint.h5" --cache "$cache" -q
grep -q '"status": "completed"' "$out/run/summary.json" || { echo "FAIL: the resumed run did not complete" >&2; exit 1; }
echo "interrupted on 2 ranks, resumed on 1 rank to the end"
