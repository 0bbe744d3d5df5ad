#!/usr/bin/env bash
# Prints the sweep: one line "problem model topology level..." per (problem, model, topology),
# levels coarse to fine. PARETO_QUICK=1 prints the small development sweep (coarse levels, no
# tet5m). Combinations left out on purpose are listed in not_applicable.tsv (and README.md).
set -euo pipefail
if [[ ${PARETO_QUICK:-0} == 1 ]]; then
  p1="10x1x1 20x2x2"; p1fem="$p1"
  p2="6x3x1 8x4x1"; p2fem="$p2"
  p3="2 4"; p3fem="2 4 6"
  topos="hex tet6m"
else
  p1="10x1x1 20x2x2 40x4x4"; p1fem="$p1 80x4x4"
  p2="8x4x1 12x6x2 16x8x2"; p2fem="$p2 24x12x3"
  p3="4 6 10"; p3fem="$p3 16"   # p3: the finest FEM hex level is the reference
  topos="hex tet5m tet6m"
fi
for p in p1 p3; do
  levels=${p}; levels=${!levels}; fem=${p}fem; fem=${!fem}
  for topo in $topos; do
    if [[ $topo == hex ]]; then echo "$p fem hex $fem"; else echo "$p fem $topo $levels"; fi
  done
  echo "$p vhex_axis hex $levels"
  for topo in $topos; do echo "$p springs $topo $levels"; done
  echo "$p hybmss hex $levels"
  for topo in $topos; do [[ $topo == hex ]] || echo "$p lloyd $topo $levels"; done
  echo "$p mss hex $levels"
done
# The nearly incompressible elements (issue 23; static only, run.sh): hex Q1/P0, tet nodal, tet10, hex27.
echo "p1 fem_q1p0 hex $p1"
echo "p1 fem_nodal tet6m $p1"
echo "p1 fem_p2p0 tet6m $p1"
echo "p1 fem_p2p1 tet6m $p1"
echo "p1 fem_q2p1 hex $p1"
echo "p2 fem_q1p0 hex $p2"
echo "p2 fem_nodal tet $p2"
echo "p2 fem_p2p0 tet $p2"
echo "p2 fem_p2p1 tet $p2"
echo "p2 fem_q2p1 hex $p2"
# The plain penalty staged by the static solver's continuation (issue 19; static only).
echo "p1 fem_staged hex $p1fem"
echo "p2 fem_staged hex $p2fem"
echo "p2 fem hex $p2fem"
echo "p2 fem tet $p2"
echo "p2 vhex_axis hex $p2"
for topo in hex tet; do echo "p2 springs $topo $p2"; done
echo "p2 hybmss hex $p2"
echo "p2 lloyd tet $p2"
