#!/usr/bin/env bash
# The implicit solver's cost per Newton iteration against mesh size on its iterative path (issue 19
# item 4): bench/scenes/solver_scaling.yaml.in (a 2N x N x N hexahedral block of Land problem 1's
# uncoupled Guccione, nearly incompressible through a soft penalty plus augmented-Lagrangian
# updates, GMRES + GAMG with the rigid-body near-null space) at N = BENCH_SCALING_SIZES (default
# 17 25 37 54 79: 9 826 ... 986 078 hexahedra; BENCH_QUICK=1: 8 17), one thread, one run each.
# Per size, from the run's summary.json: Newton and GMRES iterations, the time split (forces,
# Jacobian assembly, GAMG set-up, solves), peak resident memory; the cost per Newton iteration is
# the split's sum over the Newton iterations. A least-squares line through log(cost) against
# log(elements) over the sizes with >= 10^4 elements gives the slope (issue 19 asks <= 1.2).
# Writes OUT_JSON (default bench/results/solver_scaling.json) and, with gnuplot, a PNG beside it.
# Usage: bench/solver_scaling.sh ADAMSS_BINARY [OUT_JSON]
# Machine time: ~25 min for the default sizes (measured 2026-12-02: the 10^6-element run ~14 min, 11.3 GB peak).
set -euo pipefail
adamss=${1:?usage: solver_scaling.sh ADAMSS_BINARY [OUT_JSON]}
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here/results/solver_scaling.json}
sizes=${BENCH_SCALING_SIZES:-$([[ ${BENCH_QUICK:-0} == 1 ]] && echo "8 17" || echo "17 25 37 54 79")}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

for n in $sizes; do
  sed -e "s/@N2@/$((2 * n))/; s/@N@/$n/g" "$here/scenes/solver_scaling.yaml.in" > "$tmp/scene.yaml"
  echo "solver scaling: N = $n ($((2 * n * n * n)) hexahedra) ..."
  OMP_NUM_THREADS=1 "$adamss" run "$tmp/scene.yaml" -o "$tmp/out-$n" -q
  cp "$tmp/out-$n/summary.json" "$tmp/summary-$n.json"
done

python3 - "$out" "$tmp" $sizes <<'PY'
import json, math, platform, subprocess, sys
out, tmp, sizes = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = []
for n in sizes:
    d = json.load(open(f"{tmp}/summary-{n}.json"))
    t = d["time_split_s"]
    phase = {k: t[k]["seconds"] for k in ("forces", "jacobians", "factorisations", "solves")}
    newton = d["newton_iterations"]
    rows.append({
        "N": int(n), "elements": d["elements"], "unknowns": 3 * d["nodes"], "newton_iterations": newton,
        "linear_iterations": d["linear_iterations"], "al_updates": d["augmented_lagrangian"]["updates"],
        "max_volume_ratio_violation": d["augmented_lagrangian"]["max_volume_ratio_violation"],
        "seconds": phase, "loop_s": t["loop"], "wall_s": d["wall_time_s"],
        "peak_memory_MB": d["resident_memory_MB"]["peak"],
        "per_newton_s": sum(phase.values()) / newton,
        "per_newton_phase_s": {k: v / newton for k, v in phase.items()},
        "gmres_per_solve": d["linear_iterations"] / t["solves"]["calls"],
    })

def slope(pick):
    pts = [(math.log(r["elements"]), math.log(pick(r))) for r in rows if r["elements"] >= 1e4 and pick(r) > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)

fits = {"per_newton": slope(lambda r: r["per_newton_s"]), "memory": slope(lambda r: r["peak_memory_MB"])}
for k in ("forces", "jacobians", "factorisations", "solves"):
    fits[k] = slope(lambda r, k=k: r["per_newton_phase_s"][k])
cpu = subprocess.run(["sh", "-c", "lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1"],
                     capture_output=True, text=True).stdout.strip()
json.dump({"what": "adamss run, one thread, cost per Newton iteration on the iterative path (bench/solver_scaling.sh)",
           "cpu": cpu or platform.processor(), "runs": rows, "loglog_slopes_from_1e4_elements": fits},
          open(out, "w"), indent=1)
for r in rows:
    p = r["per_newton_phase_s"]
    print(f"{r['elements']:>8} hex, {r['unknowns']:>8} unknowns: {r['newton_iterations']} Newton, "
          f"{r['gmres_per_solve']:.1f} GMRES a solve, {r['per_newton_s']:.3f} s per Newton iteration "
          f"(forces {p['forces']:.3f}, Jacobian {p['jacobians']:.3f}, GAMG set-up {p['factorisations']:.3f}, "
          f"solves {p['solves']:.3f}), peak {r['peak_memory_MB']:.0f} MB")
print("log-log slopes over >= 1e4 elements: " + ", ".join(f"{k} {v:.3f}" for k, v in fits.items() if v is not None))
PY

if command -v gnuplot > /dev/null; then
  python3 - "$out" > "$tmp/plot.dat" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["runs"]:
    p = r["per_newton_phase_s"]
    print(r["elements"], r["per_newton_s"], p["jacobians"], p["factorisations"], p["solves"], p["forces"], r["peak_memory_MB"])
PY
  slope=$(python3 -c "import json,sys; s=json.load(open(sys.argv[1]))['loglog_slopes_from_1e4_elements']['per_newton']; print('%.2f' % s if s else '-')" "$out")
  gnuplot <<GP
set terminal pngcairo size 900,650 font ",10" noenhanced
set output "${out%.json}.png"
set title "Implicit solver, iterative path (GMRES + GAMG), one thread: cost per Newton iteration (slope ${slope})"
set logscale xy
set xlabel "hexahedra (8 Gauss points each)"
set ylabel "seconds per Newton iteration"
set y2label "peak resident memory (MB)"
set logscale y2
set y2tics
set key top left
set grid
plot "$tmp/plot.dat" u 1:2 w lp lw 2 pt 7 t "total", \
     "" u 1:5 w lp pt 5 t "GMRES solves", \
     "" u 1:4 w lp pt 9 t "GAMG set-up", \
     "" u 1:3 w lp pt 11 t "Jacobian assembly", \
     "" u 1:6 w lp pt 13 t "forces", \
     "" u 1:7 axes x1y2 w lp dt 2 pt 4 t "peak memory (right axis)"
GP
  echo "wrote ${out%.json}.png"
fi
echo "wrote $out"
