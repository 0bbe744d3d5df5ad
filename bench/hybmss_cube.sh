#!/usr/bin/env bash
# Seed 001's speed headline: the 10 x 10 x 10 HybMSS cube, dt = 1 ms, 10 000 explicit steps, for
# nu = 1/4 (springs only) and nu = 0.3 (springs + volume correction), on 1 and 2 OpenMP threads.
# Paper (i7-4790K @ 4 GHz, one thread): 2.44 s and 5.579 s.
# Each case runs BENCH_REPEAT times (default 11; 2 with BENCH_QUICK=1): the JSON keeps the
# fastest (wall_s) and the median, because on a shared virtual machine single runs of this
# 0.25 s job spread by +-20 %.
# Usage: bench/hybmss_cube.sh ADAMSS_BINARY [OUT_JSON]   (default bench/results/hybmss_cube.json)
set -euo pipefail
adamss=${1:?usage: hybmss_cube.sh ADAMSS_BINARY [OUT_JSON]}
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here/results/hybmss_cube.json}
repeat=${BENCH_REPEAT:-$([[ ${BENCH_QUICK:-0} == 1 ]] && echo 2 || echo 11)}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)
rows=""
for nu in 0.25 0.3; do
  sed "s/@NU@/$nu/g" "$here/scenes/hybmss_cube.yaml.in" > "$tmp/cube.yaml"
  paper=$([[ $nu == 0.25 ]] && echo 2.44 || echo 5.579)
  for threads in 1 2; do
    : > "$tmp/walls"
    for ((r = 0; r < repeat; ++r)); do
      OMP_NUM_THREADS=$threads OMP_WAIT_POLICY=passive "$adamss" run "$tmp/cube.yaml" -o "$tmp/out" -q
      sed -n 's/.*"wall_time_s": *\([0-9.e+-]*\).*/\1/p' "$tmp/out/summary.json" | head -1 >> "$tmp/walls"
    done
    steps=$(sed -n 's/.*"steps": *\([0-9]*\).*/\1/p' "$tmp/out/summary.json" | head -1)
    read -r best median worst < <(sort -g "$tmp/walls" | awk '{a[NR] = $1} END {print a[1], a[int((NR + 1) / 2)], a[NR]}')
    speedup=$(awk -v p="$paper" -v w="$best" 'BEGIN {printf "%.2f", p / w}')
    speedup_median=$(awk -v p="$paper" -v w="$median" 'BEGIN {printf "%.2f", p / w}')
    echo "nu = $nu, $threads thread(s): $steps steps, fastest of $repeat $best s, median $median s, slowest $worst s" \
      "(paper, one thread: $paper s; x$speedup fastest, x$speedup_median median)"
    rows="$rows${rows:+,}
    {\"nu\": $nu, \"threads\": $threads, \"steps\": $steps, \"wall_s\": $best, \"wall_median_s\": $median, \"wall_max_s\": $worst, \"repeats\": $repeat, \"paper_wall_s\": $paper, \"speedup\": $speedup, \"speedup_median\": $speedup_median}"
  done
done
cat > "$out" <<JSON
{
  "case": "seed 001 HybMSS cube: 10x10x10 cells of 0.5 m, E = 10 kPa, dt = 1 ms, 10 000 steps, symplectic Euler",
  "note": "wall_s is the fastest of the repeats (wall_time_s of adamss run: setup, stepping and output); wall_median_s their median",
  "machine": {"cpu": "$cpu", "cores": $(nproc)},
  "runs": [$rows
  ]
}
JSON
echo "wrote $out"
