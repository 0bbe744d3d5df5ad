#!/usr/bin/env bash
# Strong scaling on this machine's cores (issue 22, docs/parallel.md): each scene on 1 rank
# (OpenMP threads on both cores, the default) and under `mpirun -np 2` (one thread per rank), plus
# 1 rank with one thread; BENCH_REPEAT runs each (default 3), the median of the whole command's
# wall time kept. PETSc's -log_view (rank 0, max over ranks) gives the numerical LU time
# (MatLUFactorNum) where the scene solves linear systems.
# Writes OUT_JSON (default bench/results/mpi.json) and prints one line per scene and setting.
# Usage: bench/mpi.sh ADAMSS_BINARY [OUT_JSON]
set -euo pipefail
adamss=${1:?usage: mpi.sh ADAMSS_BINARY [OUT_JSON]}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
out=${2:-$here/results/mpi.json}
repeat=${BENCH_REPEAT:-3}
cache=${ADAMSS_CACHE_DIR:-$root/build/mesh-cache}
scenes=${BENCH_MPI_SCENES:-"cases/benchmarks/land-p2.yaml cases/quick/lv_twitch_symplectic.yaml cases/anatomy/biv-inflation-coarse.yaml"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
lu_time() { awk '$1 == "MatLUFactorNum" {print $4; found = 1} END {if (!found) print 0}' "$1"; }

rows=""
for scene in $scenes; do
  name=$(basename "$scene" .yaml)
  for setting in "1rank_2threads" "1rank_1thread" "2ranks"; do
    : > "$tmp/walls"
    : > "$tmp/lus"
    for ((r = 0; r < repeat; ++r)); do
      rm -rf "$tmp/out"
      start=$(date +%s.%N)
      case $setting in
        1rank_2threads) PETSC_OPTIONS="-log_view :$tmp/log.txt" "$adamss" run "$root/$scene" -o "$tmp/out" --cache "$cache" -q ;;
        1rank_1thread) OMP_NUM_THREADS=1 PETSC_OPTIONS="-log_view :$tmp/log.txt" "$adamss" run "$root/$scene" -o "$tmp/out" --cache "$cache" -q ;;
        2ranks) mpirun -np 2 -x PETSC_OPTIONS="-log_view :$tmp/log.txt" "$adamss" run "$root/$scene" -o "$tmp/out" --cache "$cache" -q ;;
      esac
      end=$(date +%s.%N)
      awk -v a="$start" -v b="$end" 'BEGIN {printf "%.3f\n", b - a}' >> "$tmp/walls"
      if [[ -s $tmp/log.txt ]]; then lu_time "$tmp/log.txt" >> "$tmp/lus"; else echo 0 >> "$tmp/lus"; fi
      rm -f "$tmp/log.txt"
    done
    wall=$(median < "$tmp/walls")
    lu=$(median < "$tmp/lus")
    newton=$(sed -n 's/.*"newton_iterations": \([0-9]*\).*/\1/p' "$tmp/out/summary.json")
    printf '%-28s %-15s wall %8.3f s  LU %8.3f s  Newton %s\n' "$name" "$setting" "$wall" "$lu" "${newton:-0}"
    rows+="${rows:+,}"$'\n'"  {\"scene\": \"$scene\", \"setting\": \"$setting\", \"wall_s\": $wall, \"lu_s\": $lu, \"newton\": ${newton:-0}, \"runs\": $repeat}"
  done
done
printf '{"date": "%s", "machine": "%s cores", "runs": [%s\n]}\n' "$(date -u +%F)" "$(nproc)" "$rows" > "$out"
echo "wrote $out"
