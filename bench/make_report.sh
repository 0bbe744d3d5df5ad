#!/usr/bin/env bash
# Assembles bench/report.md from the benchmark results (issue 9): machine, STREAM bandwidth, kernel
# table with bytes/flops per element and the fraction of STREAM triad, roofline, linear-scaling fit
# of the explicit step, the HybMSS cube, and the Pareto section if bench/pareto/run.sh wrote one.
# Needs bash, awk, gnuplot (no python, no jq).
# Usage: bench/make_report.sh RESULTS_DIR [BUILD_DIR] [REPORT_MD]
#   RESULTS_DIR  holds stream.json, kernels.json, hybmss_cube.json, solver.json (+ pareto.md, pareto_*.png)
#   BUILD_DIR    the CMake build the binaries came from (compiler and flags); default build
#   REPORT_MD    default: RESULTS_DIR/../report.md
# Writes RESULTS_DIR/machine.json, scaling.json, kernel_table.tsv, roofline.png, scaling.png.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
res=$(cd "${1:?usage: make_report.sh RESULTS_DIR [BUILD_DIR] [REPORT_MD]}" && pwd)
build=${2:-build}
report=${3:-$(dirname "$res")/report.md}
costs=$here/kernel_costs.json
resrel=$(realpath --relative-to="$(dirname "$report")" "$res")
date_tag=${BENCH_DATE:-$(date +%F)}

# ---------------------------------------------------------------- machine
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)
cores=$(nproc)
mhz=$(awk -F: '/^cpu MHz/ {gsub(/ /, "", $2); print $2; exit}' /proc/cpuinfo 2>/dev/null || echo 0)
cache=$build/CMakeCache.txt
cval() { [[ -f $cache ]] && sed -n "s/^$1:[A-Z]*=//p" "$cache" | head -1 || true; }
cxx=$(cval CMAKE_CXX_COMPILER)
cxx_version=$([[ -n $cxx ]] && "$cxx" --version 2>/dev/null | head -1 || echo unknown)
flags="$(cval CMAKE_CXX_FLAGS) $(cval CMAKE_CXX_FLAGS_RELEASE)"
flags=$(echo "$flags" | sed 's/^ *//; s/ *$//')
build_type=$(cval CMAKE_BUILD_TYPE)
has_avx512=$(grep -q avx512f /proc/cpuinfo 2>/dev/null && echo yes || echo no)
# Peak double-precision flops. Zen 4 has two 256-bit FMA pipes (AVX-512 instructions are split in
# two 256-bit halves): 2 x 4 lanes x 2 = 16 flop/cycle/core. The code as built (no -march: baseline
# x86-64, SSE2, no FMA) can at best issue 2 multiplies + 2 adds of 2 lanes: 8 flop/cycle/core.
ghz=$(awk -v m="$mhz" 'BEGIN {printf "%.3f", m / 1000}')
peak_hw=$(awk -v c="$cores" -v g="$ghz" 'BEGIN {printf "%.1f", c * g * 16}')
peak_sse=$(awk -v c="$cores" -v g="$ghz" 'BEGIN {printf "%.1f", c * g * 8}')
cat > "$res/machine.json" <<JSON
{
  "date": "$date_tag",
  "cpu": "$cpu",
  "cores": $cores,
  "cpu_mhz_proc_cpuinfo": $mhz,
  "avx512": "$has_avx512",
  "compiler": "$cxx_version",
  "build_type": "$build_type",
  "cxx_flags": "$flags",
  "peak_gflops_avx512_fma": $peak_hw,
  "peak_gflops_sse2_as_built": $peak_sse,
  "note": "shared machine: 2 cores used by several people at once; numbers are upper bounds on cost"
}
JSON

# ---------------------------------------------------------------- STREAM
stream=$res/stream.json
triad1=0
triad2=0
stream_rows=""
if [[ -f $stream ]]; then
  stream_rows=$(awk -F'[:,}]' '/"threads"/ {printf "| %s | %s | %s | %s | %s |\n", $2+0, $4+0, $6+0, $8+0, $10+0}' "$stream")
  triad1=$(awk -F'[:,}]' '/"threads": 1,/ {print $10+0}' "$stream")
  triad2=$(awk -F'[:,}]' '/"threads": 2,/ {print $10+0}' "$stream")
  array_mb=$(awk -F'[:,]' '/"array_mb"/ {print $2+0}' "$stream")
fi

# ---------------------------------------------------------------- kernels
# Google Benchmark JSON: one "key": value per line inside each benchmark object.
kjson=$res/kernels.json
raw=$res/.kernels_raw.tsv
: > "$raw"
if [[ -f $kjson ]]; then
  awk '
    /"name":/ && !/"family_index"/ { n = $0; sub(/.*"name": *"/, "", n); sub(/".*/, "", n) }
    /"ns_per_element":/ { v = $2; sub(/,/, "", v); ns = v }
    /"elements":/ { v = $2; sub(/,/, "", v); el = v }
    /"nodes":/ { v = $2; sub(/,/, "", v); nd = v }
    /"real_time":/ { v = $2; sub(/,/, "", v); rt = v }
    /"cpu_time":/ { v = $2; sub(/,/, "", v); ct = v }
    /"error_occurred":/ { err = 1 }
    /^    }/ { if (n != "" && ns != "" && !err) printf "%s\t%s\t%s\t%s\t%s\t%s\n", n, el, nd, ns, rt, ct; n = ""; ns = ""; el = ""; nd = ""; rt = ""; ct = ""; err = 0 }
  ' "$kjson" > "$raw"
fi
# How busy the machine was: Google Benchmark's load average at the start of the kernel run, and the
# median share of a core the 1-thread benchmarks got (CPU time / wall time; 1 = the core was ours).
load_avg=$( [[ -f $kjson ]] && sed -n 's/.*"load_avg": *\[\(.*\)\].*/\1/p' "$kjson" | head -1 | sed 's/,/, /g' || true)
core_share=$(awk -F'\t' '$1 ~ /threads:1\// && $5 > 0 {print $6 / $5}' "$raw" | sort -g | awk '{v[NR] = $1} END {if (NR) printf "%.0f", 100 * v[int((NR + 1) / 2)]; else print "?"}')
# costs: "case/term": {"items_per_element": x, "stencil": n, "reads_v": b, "const_bytes": c, "flops": f, ...}
costs_tsv=$res/.costs.tsv
awk '
  /^    "[a-z_]+\/[a-z_]+": *\{/ {
    k = $0; sub(/^ *"/, "", k); sub(/".*/, "", k)
    line = $0
    ipe = line; sub(/.*"items_per_element": */, "", ipe); sub(/,.*/, "", ipe)
    st = line; sub(/.*"stencil": */, "", st); sub(/,.*/, "", st)
    rv = line; sub(/.*"reads_v": */, "", rv); sub(/,.*/, "", rv)
    cb = line; sub(/.*"const_bytes": */, "", cb); sub(/,.*/, "", cb)
    fl = line; sub(/.*"flops": */, "", fl); sub(/,.*/, "", fl)
    printf "%s\t%s\t%s\t%s\t%s\t%s\n", k, ipe, st, (rv == "true" ? 1 : 0), cb, fl
  }' "$costs" > "$costs_tsv"

# One row per forces/jacobian benchmark: mode case term N threads elements nodes ns/el
#   + flops/el bytes/el (compulsory) impl_bytes/el GFLOP/s GB/s fraction-of-triad
table=$res/kernel_table.tsv
awk -F'\t' -v t1="$triad1" -v t2="$triad2" '
  FNR == NR { ipe[$1] = $2; st[$1] = $3; rv[$1] = $4; cb[$1] = $5; fl[$1] = $6; next }
  {
    split($1, p, "/"); mode = p[1]
    if (mode != "forces" && mode != "jacobian") next
    key = p[2] "/" p[3]; thr = p[5]; sub(/threads:/, "", thr)
    el = $2; nd = $3; ns = $4; cns = ($5 > 0 ? ns * $6 / $5 : 0)
    if (!(key in fl)) { printf "%s\t%s\t%s\t%s\t%s\t%.0f\t%.0f\t%.2f\t-\t-\t-\t-\t-\t-\t%.2f\n", mode, p[2], p[3], p[4], thr, el, nd, ns, cns; next }
    npe = nd / el
    fpe = ipe[key] * fl[key]
    bpe = npe * (24 + 24 * rv[key] + 48) + ipe[key] * cb[key]
    ibpe = bpe + ipe[key] * st[key] * 56 + (rv[key] ? 0 : npe * 24)
    gf = fpe / ns; gb = bpe / ns
    tr = (thr == 1 ? t1 : t2)
    printf "%s\t%s\t%s\t%s\t%s\t%.0f\t%.0f\t%.2f\t%.0f\t%.0f\t%.0f\t%.3f\t%.3f\t%.3f\t%.2f\n", mode, p[2], p[3], p[4], thr, el, nd, ns, fpe, bpe, ibpe, gf, gb, (tr > 0 ? gb / tr : 0), cns
  }' "$costs_tsv" "$raw" > "$table"

# ---------------------------------------------------------------- roofline
bw=${triad2:-0}
if [[ -s $table ]] && awk -v b="$bw" 'BEGIN {exit !(b > 0)}'; then
  # every kernel is measured at 10^5 (the 10^6 runs cover only a few); the largest size otherwise (quick mode)
  big=$(awk -F'\t' '$1 == "forces" && $9 != "-" {print $4}' "$table" | sort -n | uniq | awk '$1 <= 100000' | tail -1)
  for t in 1 2; do
    awk -F'\t' -v n="$big" -v t="$t" '$1 == "forces" && $4 == n && $5 == t && $9 != "-" {printf "%g %g \"%s\"\n", $9 / $10, $12, ($2 == $3 ? $3 : $2 ":" $3)}' "$table" > "$res/.roof$t.dat"
  done
  gnuplot <<GP
set terminal pngcairo size 1000,700 font ",10" noenhanced
set output "$res/roofline.png"
set title "Roofline, forces only, ${big} elements (AI: hand-counted flops / compulsory bytes per element)"
set logscale xy
set xlabel "arithmetic intensity (flop/byte)"
set ylabel "GFLOP/s"
set xrange [0.05:50]
set yrange [0.01:$(awk -v p="$peak_hw" 'BEGIN {print p * 2}')]
set key bottom right
set grid
bw1 = $triad1
bw2 = $triad2
p1 = $peak_hw
p2 = $peak_sse
plot min(x, y) = (x < y ? x : y), \
  min(p1, bw2 * x) w l lw 2 lc rgb "black" t sprintf("STREAM triad 2 thr %.1f GB/s, peak AVX-512 FMA %.0f GFLOP/s", bw2, p1), \
  min(p2, bw2 * x) w l lw 1 dt 2 lc rgb "gray40" t sprintf("peak as built (SSE2, no FMA) %.0f GFLOP/s", p2), \
  min(p1 / 2, bw1 * x) w l lw 1 dt 3 lc rgb "gray60" t sprintf("1 thread: triad %.1f GB/s, %.0f GFLOP/s", bw1, p1 / 2), \
  "$res/.roof1.dat" u 1:2 w p pt 7 ps 1.3 lc rgb "#1f77b4" t "1 thread", \
  "$res/.roof2.dat" u 1:2 w p pt 5 ps 1.3 lc rgb "#d62728" t "2 threads", \
  "$res/.roof2.dat" u 1:2:3 w labels left offset 1,0 font ",8" notitle
GP
fi

# ---------------------------------------------------------------- scaling of the explicit step
scal=$res/scaling.json
steps=$res/.steps.tsv
awk -F'\t' '{split($1, p, "/"); if (p[1] != "step") next; t = p[4]; sub(/threads:/, "", t); printf "%s\t%s\t%.0f\t%.6g\t%.4f\n", p[2], t, $2, $4 * $2 * 1e-6, $4}' "$raw" > "$steps"
fits=$res/.fits.tsv
: > "$fits"
if [[ -s $steps ]]; then
  # least squares t = a + b n per (case, threads); R^2 = 1 - SS_res / SS_tot
  awk -F'\t' '
    { k = $1 "\t" $2; n[k]++; X[k, n[k]] = $3; Y[k, n[k]] = $4 }
    END {
      for (k in n) {
        m = n[k]; sx = sy = sxx = sxy = 0
        for (i = 1; i <= m; i++) { sx += X[k, i]; sy += Y[k, i]; sxx += X[k, i] ^ 2; sxy += X[k, i] * Y[k, i] }
        d = m * sxx - sx * sx; b = (m * sxy - sx * sy) / d; a = (sy - b * sx) / m
        ybar = sy / m; sst = ssr = 0
        for (i = 1; i <= m; i++) { sst += (Y[k, i] - ybar) ^ 2; ssr += (Y[k, i] - a - b * X[k, i]) ^ 2 }
        nmin = nmax = X[k, 1]
        for (i = 1; i <= m; i++) { if (X[k, i] < nmin) nmin = X[k, i]; if (X[k, i] > nmax) nmax = X[k, i] }
        # log-log slope p of t ~ n^p (1 = linear; not dominated by the largest size like R^2 above)
        lx = ly = lxx = lxy = 0; rmin = 1e300; rmax = 0
        for (i = 1; i <= m; i++) {
          u = log(X[k, i]); w = log(Y[k, i]); lx += u; ly += w; lxx += u * u; lxy += u * w
          r = Y[k, i] / X[k, i] * 1e6; if (r < rmin) rmin = r; if (r > rmax) rmax = r
        }
        p = (m * lxy - lx * ly) / (m * lxx - lx * lx)
        printf "%s\t%.6g\t%.6g\t%.6f\t%d\t%.0f\t%.0f\t%.4f\t%.1f\t%.1f\n", k, a, b, 1 - ssr / sst, m, nmin, nmax, p, rmin, rmax
      }
    }' "$steps" | sort > "$fits"
  {
    echo "{"
    echo "  \"model\": \"t_step_ms = a_ms + b_ms_per_element * n (least squares over the measured sizes)\","
    echo "  \"fits\": ["
    awk -F'\t' '{printf "%s    {\"case\": \"%s\", \"threads\": %s, \"a_ms\": %s, \"b_ms_per_element\": %s, \"b_ns_per_element\": %.2f, \"r2\": %s, \"points\": %s, \"n_min\": %s, \"n_max\": %s, \"loglog_slope\": %s, \"ns_per_element_min\": %s, \"ns_per_element_max\": %s}", (NR > 1 ? ",\n" : ""), $1, $2, $3, $4, $4 * 1e6, $5, $6, $7, $8, $9, $10, $11} END {print ""}' "$fits"
    echo "  ],"
    echo "  \"points\": ["
    awk -F'\t' '{printf "%s    {\"case\": \"%s\", \"threads\": %s, \"elements\": %s, \"ms_per_step\": %s, \"ns_per_element\": %s}", (NR > 1 ? ",\n" : ""), $1, $2, $3, $4, $5} END {print ""}' "$steps"
    echo "  ]"
    echo "}"
  } > "$scal"
  plotcmd=""
  plotns=""
  i=0
  colors=("#1f77b4" "#d62728" "#2ca02c" "#9467bd")
  while IFS=$'\t' read -r c t a b r2 m lo hi p rmin rmax; do
    awk -F'\t' -v c="$c" -v t="$t" '$1 == c && $2 == t {print $3, $4, $5}' "$steps" | sort -n > "$res/.s_${c}_$t.dat"
    col=${colors[$((i % 4))]}
    plotcmd+="\"$res/.s_${c}_$t.dat\" u 1:2 w p pt 7 lc rgb \"$col\" t \"$c, $t thr (R² = $(printf %.4f "$r2"), b = $(awk -v b="$b" 'BEGIN {printf "%.0f", b * 1e6}') ns/element)\", "
    plotcmd+="(x >= $lo && x <= $hi ? $a + $b * x : 1/0) w l lc rgb \"$col\" notitle, "
    plotns+="\"$res/.s_${c}_$t.dat\" u 1:3 w lp pt 7 lc rgb \"$col\" t \"$c, $t thr (t ~ n^$(printf %.3f "$p"))\", "
    i=$((i + 1))
  done < "$fits"
  gnuplot <<GP
set terminal pngcairo size 1400,600 font ",10" noenhanced
set output "$res/scaling.png"
set multiplot layout 1,2 title "One symplectic-Euler step of the whole model vs element count"
set logscale xy
set xlabel "elements"
set ylabel "ms per step"
set title "wall time per step and the least-squares line t = a + b n"
set key top left
set grid
set samples 400
set xrange [500:2e6]
plot ${plotcmd%, }
unset logscale y
set yrange [0:*]
set ylabel "ns per element-step"
set title "cost per element (flat = linear scaling)"
set key bottom right
plot ${plotns%, }
unset multiplot
GP
fi

# ---------------------------------------------------------------- report
{
  echo "# Benchmarks: cost per element, roofline, scaling"
  echo
  echo "Generated by \`bench/make_report.sh\` (\`make bench\`) on $date_tag. The machine is **shared**"
  echo "(2 cores used by several people compiling and running at the same time): every time below is"
  echo "an upper bound on the cost, and the 2-thread numbers in particular are pessimistic."
  echo
  echo "## Machine"
  echo
  echo "| | |"
  echo "|---|---|"
  echo "| CPU | $cpu (AMD Zen 4, family 25 model 17; KVM guest) |"
  echo "| cores | $cores (1 thread per core) |"
  echo "| clock | $ghz GHz (\`cpu MHz\` of /proc/cpuinfo: the guest sees the nominal TSC rate, not the boost clock) |"
  echo "| peak DP | $peak_hw GFLOP/s = $cores cores x $ghz GHz x 16 flop/cycle (two 256-bit FMA pipes; AVX-512 runs as two halves) |"
  echo "| peak as built | $peak_sse GFLOP/s = 8 flop/cycle/core: the flags below have no -march, so the code is SSE2 without FMA |"
  echo "| compiler | $cxx_version |"
  echo "| build | $build_type, CMAKE_CXX_FLAGS + CMAKE_CXX_FLAGS_RELEASE = \`$flags\` |"
  echo "| load | load average ${load_avg:-?} (1, 5, 15 min) when the kernel benchmarks started; the 1-thread kernel runs got a median ${core_share} % of a core (CPU time / wall time) |"
  echo
  echo "## Memory bandwidth (bench/stream.cpp)"
  echo
  if [[ -n $stream_rows ]]; then
    echo "STREAM-like kernels on 3 arrays of ${array_mb} MB (L3 is 32 MB), best of 10, GB/s = 1e9 B/s counted as"
    echo "STREAM does (copy/scale 16 B, add/triad 24 B per index)."
    echo
    echo "| threads | copy | scale | add | triad |"
    echo "|---|---|---|---|---|"
    echo "$stream_rows"
  else
    echo "(no stream.json)"
  fi
  echo
  echo "## Force kernels (bench/bench_forces.cpp)"
  echo
  echo "ns per element per evaluation (wall time / (elements x evaluations)) on box meshes with a uniform"
  echo "fibre frame, nodes displaced randomly by 1 % of an edge. \`jacobian\` = add_forces + add_jacobian"
  echo "into a sink that only sums the blocks (add_jacobian is serial, so its 2-thread column measures the"
  echo "parallel forces part only). flop and byte counts per element are the hand counts of"
  echo "\`bench/kernel_costs.json\` (rule in bench/README.md); GB/s is the compulsory traffic divided by the"
  echo "time, and \"of triad\" compares it with STREAM triad at the same thread count. The \"impl. B\""
  echo "column adds what the StencilTerm assembler moves on top (per-item force buffer, scatter table,"
  echo "gathered velocities). In the jacobian tables the flop and byte columns are left out (the counts"
  echo "are for the forces only). \"(CPU)\" is the 1-thread time scaled by CPU time / wall time of the"
  echo "benchmark thread: roughly what the kernel costs when the core is not shared (see \"load\" above)."
  echo
  if [[ -s $table ]]; then
    for mode in forces jacobian; do
      echo "### ${mode}"
      echo
      echo "| case / term | elements | ns/el 1 thr | (CPU) | ns/el 2 thr | flop/el | B/el | impl. B/el | GFLOP/s (2 thr) | GB/s (2 thr) | of triad |"
      echo "|---|---|---|---|---|---|---|---|---|---|---|"
      awk -F'\t' -v m="$mode" '
        $1 == m { k = $2 " / " $3 SUBSEP $4; keys[k] = 1; el[k] = $6; ns[k, $5] = $8; if ($5 == 1) cpu[k] = $15; fl[k] = $9; b[k] = $10; ib[k] = $11; gf[k, $5] = $12; gb[k, $5] = $13; fr[k, $5] = $14
          if (m == "jacobian") { fl[k] = b[k] = ib[k] = gf[k, $5] = gb[k, $5] = fr[k, $5] = "-" } }
        END {
          for (k in keys) {
            split(k, q, SUBSEP)
            printf "%s\t%012d\t| %s | %.0f | %s | %.0f | %s | %s | %s | %s | %s | %s | %s |\n", q[1], q[2], q[1], el[k], ns[k, 1], cpu[k], ns[k, 2], fl[k], b[k], ib[k], gf[k, 2], gb[k, 2], (fr[k, 2] == "-" ? "-" : sprintf("%.0f %%", 100 * fr[k, 2]))
          }
        }' "$table" | sort -t$'\t' -k1,1 -k2,2n | cut -f3
      echo
    done
  else
    echo "(no kernels.json)"
    echo
  fi
  if [[ -f $res/roofline.png ]]; then
    echo "![roofline]($resrel/roofline.png)"
    echo
    echo "Roofline: each point is one force term at about $big elements (meshes beyond the 32 MB L3),"
    echo "arithmetic intensity = hand-counted flops / compulsory bytes, achieved GFLOP/s = flops / measured"
    echo "time. A point on the slanted line would be bandwidth-bound, one on a flat line compute-bound;"
    echo "the distance below both is what the assembler (gather, per-item buffer, per-node sum) and"
    echo "the scalar SSE2 arithmetic cost. Below about 10^5 elements the working set fits in L2/L3"
    echo "(32 MB), so \"of triad\" can exceed 100 % there; it is meaningful at the largest sizes."
    echo
  fi
  echo "## Explicit step, linear scaling"
  echo
  if [[ -s $fits ]]; then
    echo "One symplectic-Euler step of the whole model (force evaluation, a = f/m with constraints,"
    echo "update, end_step hooks; no output and no per-step flat-element check) at dt = critical/10."
    echo "Least-squares fit of the wall time per step t = a + b n over the measured sizes"
    echo "(\`$resrel/scaling.json\`). With sizes spread over three decades the plain R^2 is decided by the"
    echo "largest meshes, so the table also gives the slope of log t against log n (1 = linear) and the"
    echo "range of the cost per element-step; the right panel of the plot shows the latter."
    echo
    echo "| case | threads | sizes | a (ms) | b (ns/element) | R^2 | log-log slope | ns/element min .. max |"
    echo "|---|---|---|---|---|---|---|---|"
    awk -F'\t' '{printf "| %s | %s | %d points, %s .. %s | %.3f | %.1f | %.5f | %.3f | %.0f .. %.0f |\n", $1, $2, $6, $7, $8, $3, $4 * 1e6, $5, $9, $10, $11}' "$fits"
    echo
    echo "| case | threads | elements | ms/step | ns/element |"
    echo "|---|---|---|---|---|"
    sort -t$'\t' -k1,1 -k2,2n -k3,3n "$steps" | awk -F'\t' '{printf "| %s | %s | %s | %.3f | %.1f |\n", $1, $2, $3, $4, $5}'
    echo
    echo "![scaling]($resrel/scaling.png)"
  else
    echo "(no step benchmarks in kernels.json)"
  fi
  echo
  echo "## HybMSS cube (bench/hybmss_cube.sh)"
  echo
  if [[ -f $res/hybmss_cube.json ]]; then
    echo "Seed 001's 10 x 10 x 10 cube, 10 000 symplectic-Euler steps (\`adamss run\`, wall time of the run"
    echo "including setup and output; fastest and median of the repeats)."
    echo
    echo "| nu | threads | steps | wall, fastest (s) | wall, median (s) | repeats | paper, i7-4790K 1 thread (s) | speed-up (fastest / median) |"
    echo "|---|---|---|---|---|---|---|---|"
    awk -F'[:,}]' '/"nu"/ {printf "| %s | %s | %s | %s | %s | %s | %s | %s / %s |\n", $2+0, $4+0, $6+0, $8+0, $10+0, $14+0, $16+0, $18+0, $20+0}' "$res/hybmss_cube.json"
  else
    echo "(no hybmss_cube.json)"
  fi
  echo
  echo "## Implicit solver (bench/solver.sh)"
  echo
  if [[ -f $res/solver.json ]]; then
    echo "Static benchmark scenes, one thread, fastest of the repeats; time split from PETSc's -log_view"
    echo "(the rest of PETSc's total is residuals, Jacobian assembly, elimination and output)."
    echo
    echo "| scene | wall (s) | load steps | Newton | linear | LU factorisations (s) | solves (s) | assembly and residuals (s) |"
    echo "|---|---|---|---|---|---|---|---|"
    python3 - "$res/solver.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["runs"]:
    print(f"| {r['scene']} | {r['wall_s']:.2f} | {r['steps']} | {r['newton_iterations']} | {r['linear_iterations']} |"
          f" {r['factorisation_s']:.2f} ({r['factorisations']}) | {r['solve_s']:.2f} ({r['solves']}) | {r['assembly_and_residuals_s']:.2f} |")
PY
  else
    echo "(no solver.json)"
  fi
  echo
  echo "## Implicit solver against mesh size (bench/solver_scaling.sh)"
  echo
  if [[ -f $res/solver_scaling.json ]]; then
    echo "The iterative path (GMRES + GAMG, soft penalty + augmented Lagrangian), one thread, one run per"
    echo "size; cost per Newton iteration = (forces + Jacobians + GAMG set-ups + solves) / Newton iterations."
    echo
    echo "| hexahedra | unknowns | Newton | GMRES a solve | s per Newton iteration | Jacobian | GAMG set-up | solves | peak MB |"
    echo "|---|---|---|---|---|---|---|---|---|"
    python3 - "$res/solver_scaling.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
for r in d["runs"]:
    p = r["per_newton_phase_s"]
    print(f"| {r['elements']} | {r['unknowns']} | {r['newton_iterations']} | {r['gmres_per_solve']:.1f} | {r['per_newton_s']:.3f} |"
          f" {p['jacobians']:.3f} | {p['factorisations']:.3f} | {p['solves']:.3f} | {r['peak_memory_MB']:.0f} |")
s = d["loglog_slopes_from_1e4_elements"]
if s.get("per_newton") is not None:
    print()
    print("Log-log slopes from 10^4 elements: " + ", ".join(f"{k} {v:.2f}" for k, v in s.items() if v is not None) + ".")
PY
    if [[ -f $res/solver_scaling.png ]]; then echo; echo "![solver scaling]($resrel/solver_scaling.png)"; fi
  else
    echo "(no solver_scaling.json)"
  fi
  echo
  echo "## MPI ranks (bench/mpi.sh)"
  echo
  if [[ -f $res/mpi.json ]]; then
    echo "Whole commands (mpirun start-up included), median of the repeats; LU = MatLUFactorNum (max over"
    echo "ranks). docs/parallel.md reads these numbers and gives the scaling model."
    echo
    echo "| scene | setting | wall (s) | LU (s) | Newton |"
    echo "|---|---|---|---|---|"
    python3 - "$res/mpi.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["runs"]:
    print(f"| {r['scene']} | {r['setting']} | {r['wall_s']:.2f} | {r['lu_s']:.2f} | {r['newton']} |")
PY
  else
    echo "(no mpi.json)"
  fi
  echo
  if [[ -f $res/pareto.md ]]; then
    # pareto.md (bench/pareto/report.sh) brings its own "## Speed against error" heading.
    sed -E "s#\]\((pareto_[^)]*\.png)\)#]($resrel/\1)#g; s/^# /### /" "$res/pareto.md"
    echo
  fi
} > "$report"
rm -f "$res"/.roof*.dat "$res"/.s_*.dat "$raw" "$costs_tsv" "$steps" "$fits"
echo "wrote $report"
