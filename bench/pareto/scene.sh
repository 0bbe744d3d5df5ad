#!/usr/bin/env bash
# Prints one pareto-sweep scene (YAML) on stdout.
# Usage: scene.sh PROBLEM MODEL TOPOLOGY LEVEL SOLVER DT FITDIR
#   PROBLEM  p1 (Land beam) | p2 (Land ellipsoid) | p3 (seed 001 cube, 5 % compression)
#   MODEL    fem | vhex_axis | springs | hybmss | lloyd | mss, or the nearly incompressible elements of
#            issue 23 (uncoupled law, volume exact by the augmented Lagrangian at kappa = 2000 C; static
#            only): fem_q1p0 (hex, element mean dilatation), fem_nodal (tet, nodal volume),
#            fem_p2p0 / fem_p2p1 (the tet mesh raised to tet10; element mean / corner P1 dilatation),
#            fem_q2p1 (the hex mesh raised to hex27; the dilatation projected on a linear field per element),
#            fem_staged (hex, element volume penalty p = 1000 C reached by the static solver's continuation
#            in large load steps, the law uncoupled for p1 and coupled for p2: land-p1.yaml / land-p2.yaml)
#   TOPOLOGY hex | tet5m | tet6m (boxes) ; hex | tet (ellipsoid, Kuhn tetrahedra)
#   LEVEL    p1: NXxNYxNZ divisions of the beam; p2: NVxNUxNT of the ellipsoid; p3: n (n^3 cubes)
#   SOLVER   static | implicit (backward_euler_newton) | explicit (symplectic_euler)
#   DT       explicit step (s); ignored otherwise
#   FITDIR   folder with p1.terms / p2.terms: `adamss fit` springs for the Guccione laws
# Material matching for the linear models (hybmss, lloyd, mss): see README.md.
set -euo pipefail
problem=$1 model=$2 topo=$3 level=$4 solver=$5 dt=${6:-1e-6} fitdir=${7:-.}

# The mesh entry of a box problem: box_mesh SIZE NX NY NZ (fibres along x, sheets along y).
box_mesh() {
  printf 'box: %s\n  divisions: [%s, %s, %s]\n  topology: %s\n  fibre: [1, 0, 0]\n  sheet: [0, 1, 0]' \
    "$1" "$2" "$3" "$4" "$topo"
}

case $problem in
  p1) IFS=x read -r nx ny nz <<< "$level"
      mesh=$(box_mesh "[10 mm, 1 mm, 1 mm]" "$nx" "$ny" "$nz")
      law=guccione_land_problem1; params="{}"; vol="2000 kPa"; E=18000; nu=0.49
      staged="{from: 40 kPa, factor: 50}"; dt_staged=1; staged_uncoupled=true
      h=$(awk -v n="$nx" 'BEGIN{print 1e-2 / n}')
      ramp=0.1; t_dyn=2; rate=80; ke=1e-15; dt_static=0.1
      loads="  pressure:
    - name: bottom
      surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}
      pressure: {ramp: {to: 4 Pa, duration: @RAMP@ s}}"
      boundary="  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    fix: xyz"
      probes="    - {name: tip, point: [10 mm, 0.5 mm, 1 mm]}" ;;
  p2) IFS=x read -r nv nu_ nt <<< "$level"
      mesh="ellipsoid: land
  divisions: [$nv, $nu_, $nt]
  topology: $topo"
      law=guccione_land_problem2; params="{}"; vol="10000 kPa"; E=15000; nu=0.49; h=0
      staged="{from: 100 kPa}"; dt_staged=0.5; staged_uncoupled=false
      ramp=0.02; t_dyn=0.5; rate=300; ke=1e-11; dt_static=0.05
      loads="  pressure:
    - name: lv
      surface: {cavity: lv}
      pressure: {ramp: {to: 10 kPa, duration: @RAMP@ s}}"
      boundary="  - select: {tag: base}
    fix: xyz"
      probes="    - {name: endo_apex, point: [0, 0, -17 mm]}" ;;
  p3) n=$level
      mesh=$(box_mesh "[5 m, 5 m, 5 m]" "$n" "$n" "$n")
      law=neo_hookean; params="{E: 10000 Pa, nu: 0.25}"; vol=""; E=10000; nu=0.25
      h=$(awk -v n="$n" 'BEGIN{print 5 / n}')
      ramp=5; t_dyn=60; rate=2.5; ke=1e-5; dt_static=0.5
      loads=""
      boundary="  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 1 mm}}}
    fix: xyz
  - select: {region: {plane: {point: [0, 0, 5 m], normal: [0, 0, 1], tolerance: 1 mm}}}
    fix: xy
  - select: {region: {plane: {point: [0, 0, 5 m], normal: [0, 0, 1], tolerance: 1 mm}}}
    control: {axis: z, displacement: {ramp: {to: -0.25 m, duration: @RAMP@ s}}}"
      probes="" ;;
  *) echo "scene.sh: unknown problem $problem" >&2; exit 2 ;;
esac

# Incompressibility penalty of the Land scenes (p = 1000 C, exact element volume).
volume_term=""
[[ -n $vol ]] && volume_term="
      - volume: {p: $vol, distribution: isotropic}"
hourglass=""
[[ $topo == hex ]] && hourglass="
      - hourglass: {fraction: 0.05}"
# The issue-23 elements: uncoupled law, volume exact (augmented Lagrangian, |J - 1| <= 1e-6).
al_volume() {
  printf '\n      - volume: {p: %s, distribution: %s, augmented_lagrangian: {tolerance: 1e-6}}' "$vol" "$1"
}
case $model in
  fem_p2p0 | fem_p2p1 | fem_q2p1) mesh="$mesh
  order: 2" ;;
esac
case $model in
  fem_q1p0 | fem_p2p0) terms="      - fem_element: {law: $law, parameters: $params, uncoupled: true}$(al_volume isotropic)" ;;
  fem_nodal | fem_p2p1) terms="      - fem_element: {law: $law, parameters: $params, uncoupled: true}$(al_volume nodal)" ;;
  fem_q2p1)  terms="      - fem_element: {law: $law, parameters: $params, uncoupled: true}$(al_volume linear)" ;;
  fem_staged)
             terms="      - fem_element: {law: $law, parameters: $params, uncoupled: $staged_uncoupled}
      - volume: {p: $vol, distribution: isotropic, continuation: $staged}"
             dt_static=$dt_staged ;;
  fem)       terms="      - fem_element: {law: $law, parameters: $params}$volume_term" ;;
  vhex_axis) terms="      - virtual_hexahedron: {law: $law, parameters: $params, quadrature: axis}$volume_term$hourglass" ;;
  springs)   if [[ $problem == p3 ]]; then
               # linear springs: axial k1 = E, torsion k1 = G, volume p = lambda / 2 (README.md)
               terms="      - axial_springs: {scaling: virtual, fibre: [10 kPa], sheet: [10 kPa], normal: [10 kPa]}
      - torsion_springs: {scaling: virtual, form: cosine, fibre_sheet: [4 kPa], fibre_normal: [4 kPa], sheet_normal: [4 kPa]}
      - volume: {p: 2 kPa, distribution: isotropic}$hourglass"
             else
               terms="$(cat "$fitdir/$problem.terms")$volume_term$hourglass"
             fi ;;
  hybmss)    terms="      - hybmss: {youngs_modulus: $E Pa, poisson_ratio: $nu}" ;;
  lloyd)     terms="      - lloyd_springs: {youngs_modulus: $E Pa, volume_force: true}" ;;
  # cubic lattice with edges, face and cell diagonals, one k: E = 2.7 k / h (README.md)
  mss)       k=$(awk -v E="$E" -v h="$h" 'BEGIN{printf "%.6g", E * h / 2.7}')
             terms="      - mass_springs: {stiffness: $k N/m, diagonals: all}" ;;
  *) echo "scene.sh: unknown model $model" >&2; exit 2 ;;
esac

case $solver in
  static)   ramp=1
            integrator="{type: static, dt: $dt_static s, newton_rtol: 1e-9, max_newton: 30}"
            run="{t_end: 1 s}"; friction="" ;;
  implicit) integrator="{type: backward_euler_newton, dt: $(awk -v r=$ramp 'BEGIN{print r / 10}') s, newton_rtol: 1e-9, max_newton: 30}"
            run="{t_end: $t_dyn s, ke_threshold: $ke J, ke_after: $ramp s}"
            friction="  global_friction: {rate: $rate 1/s}" ;;
  explicit) integrator="{type: symplectic_euler, dt: $dt s, check_dt: false}"
            run="{t_end: $t_dyn s, ke_threshold: $ke J, ke_after: $ramp s}"
            friction="  global_friction: {rate: $rate 1/s}" ;;
  *) echo "scene.sh: unknown solver $solver" >&2; exit 2 ;;
esac

cat <<YAML
name: pareto-$problem-$model-$topo-$level-$solver
mesh:
  $mesh
materials:
  - name: tissue
    labels: [1]
    density: 1000 kg/m^3
    terms:
$terms
YAML
if [[ -n $loads$friction ]]; then
  echo "loads:"
  [[ -n $friction ]] && echo "$friction"
  [[ -n $loads ]] && echo "${loads//@RAMP@/$ramp}"
fi
echo "boundary:"
echo "${boundary//@RAMP@/$ramp}"
echo "integrator: $integrator"
echo "run: $run"
echo "output:"
echo "  frame_interval: 0 s"
echo "  globals_interval: $(awk -v r=$ramp 'BEGIN{print r / 10}') s"
[[ -n $probes ]] && { echo "  probes:"; echo "$probes"; }
exit 0
