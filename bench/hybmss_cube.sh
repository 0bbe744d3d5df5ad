#!/usr/bin/env bash
# Seed 001's speed headline: the 10 x 10 x 10 HybMSS cube, dt = 1 ms, 10 000 explicit steps, for
# nu = 1/4 (springs only) and nu = 0.3 (springs + volume correction), on 1 and 2 OpenMP threads.
# Paper (i7-4790K @ 4 GHz, one thread): 2.44 s and 5.579 s.
# Usage: bench/hybmss_cube.sh ADAMSS_BINARY [OUT_JSON]   (default bench/results/hybmss_cube.json)
set -euo pipefail
adamss=${1:?usage: hybmss_cube.sh ADAMSS_BINARY [OUT_JSON]}
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here/results/hybmss_cube.json}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)
rows=""
for nu in 0.25 0.3; do
  sed "s/@NU@/$nu/g" "$here/scenes/hybmss_cube.yaml.in" > "$tmp/cube.yaml"
  for threads in 1 2; do
    OMP_NUM_THREADS=$threads OMP_WAIT_POLICY=passive "$adamss" run "$tmp/cube.yaml" -o "$tmp/out" -q
    wall=$(sed -n 's/.*"wall_time_s": *\([0-9.e+-]*\).*/\1/p' "$tmp/out/summary.json" | head -1)
    steps=$(sed -n 's/.*"steps": *\([0-9]*\).*/\1/p' "$tmp/out/summary.json" | head -1)
    paper=$([[ $nu == 0.25 ]] && echo 2.44 || echo 5.579)
    echo "nu = $nu, $threads thread(s): $steps steps in $wall s (paper, one thread: $paper s)"
    rows="$rows${rows:+,}
    {\"nu\": $nu, \"threads\": $threads, \"steps\": $steps, \"wall_s\": $wall, \"paper_wall_s\": $paper}"
  done
done
cat > "$out" <<JSON
{
  "case": "seed 001 HybMSS cube: 10x10x10 cells of 0.5 m, E = 10 kPa, dt = 1 ms, 10 000 steps, symplectic Euler",
  "machine": {"cpu": "$cpu", "cores": $(nproc)},
  "runs": [$rows
  ]
}
JSON
echo "wrote $out"
