#!/usr/bin/env bash
# Seed 000 sec. 2.8.2, Fig. 2.28: relative volume change of a hanging 6 x 6 x 12 hexahedral
# cuboid for volume-preservation coefficients p = 1e2 ... 1e5 kPa.
#
#   cases/benchmarks/gravity-volume.sh OUTDIR [ADAMSS]
#
# Runs the four scenes gravity-volume-p1e{2,3,4,5}.yaml into OUTDIR/p1eN/ and draws
# dV/V0 (%) over time, one curve per p (red, green, blue, magenta as in Fig. 2.28), into
# OUTDIR/gravity-volume.png with gnuplot (headless: pngcairo, else png). Prints a table of
# max |dV/V0|, final dV/V0, steps, Newton/linear iterations and wall time per scene.
# ADAMSS defaults to build/app/adamss of this repository; OMP_NUM_THREADS defaults to 1.
set -euo pipefail

if [ $# -lt 1 ]; then
  echo "usage: $0 OUTDIR [ADAMSS]" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$1"
adamss="${2:-$root/build/app/adamss}"
[ -x "$adamss" ] || { echo "$0: $adamss not found (build the adamss target first)" >&2; exit 2; }
command -v gnuplot >/dev/null || { echo "$0: gnuplot not found (scripts/install-deps installs gnuplot-nox)" >&2; exit 2; }
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
mkdir -p "$out"

exps=(2 3 4 5)
for e in "${exps[@]}"; do
  "$adamss" run "$here/gravity-volume-p1e$e.yaml" -o "$out/p1e$e" -q
done

# Table: awk reads globals.csv by column name, summary.json by key (one key per line).
printf '%-8s %14s %14s %6s %8s %8s %8s\n' "p (kPa)" "max|dV/V0| %" "final dV/V0 %" steps newton linear "wall s"
for e in "${exps[@]}"; do
  d="$out/p1e$e"
  read -r mx fin < <(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    { v = $c["volume_change"]; a = v < 0 ? -v : v; if (a > m) m = a; last = v }
    END { printf "%.4g %.4g\n", 100 * m, 100 * last }' "$d/globals.csv")
  key() { sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$d/summary.json" | head -1; }
  printf '%-8s %14s %14s %6s %8s %8s %8s\n' "1e$e" "$mx" "$fin" "$(key steps)" "$(key newton_iterations)" \
    "$(key linear_iterations)" "$(printf '%.1f' "$(key wall_time_s)")"
done

# gnuplot: columns by name (t, volume_change) so added columns do not break the plot.
term="pngcairo size 900,600 font ',11'"
gnuplot -e "set terminal pngcairo" >/dev/null 2>&1 || term="png size 900,600"
gnuplot <<EOF
set terminal $term
set output '$out/gravity-volume.png'
set datafile separator ','
set datafile columnheaders
set key top right
set grid
set xlabel 't (s)'
set ylabel 'dV/V0 (%)'
set title 'Hanging 6x6x12 hexahedral cuboid: relative volume change (seed 000 Fig. 2.28)'
plot '$out/p1e2/globals.csv' using (column('t')):(100*column('volume_change')) with lines lw 2 lc rgb 'red' title 'p = 10^2 kPa', \
     '$out/p1e3/globals.csv' using (column('t')):(100*column('volume_change')) with lines lw 2 lc rgb 'green' title 'p = 10^3 kPa', \
     '$out/p1e4/globals.csv' using (column('t')):(100*column('volume_change')) with lines lw 2 lc rgb 'blue' title 'p = 10^4 kPa', \
     '$out/p1e5/globals.csv' using (column('t')):(100*column('volume_change')) with lines lw 2 lc rgb 'magenta' title 'p = 10^5 kPa'
EOF
echo "wrote $out/gravity-volume.png"
