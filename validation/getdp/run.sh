#!/usr/bin/env bash
# Cross-check of mrbrake's axisymmetric magnetostatic solver against GetDP on the same Gmsh mesh.
# Optional validation (needs the Debian packages getdp and gmsh, and python3); see README.md.
#
#   validation/getdp/run.sh            # committed pot-core mesh + a fine mesh from the .geo
#   FINE_CLSCALE= validation/getdp/run.sh   # committed mesh only
#
# Environment: MRBRAKE (path of an mrbrake binary; default: cargo build --release -p mrbrake-cli),
# OUT (work directory, default validation/getdp/out), FINE_CLSCALE (gmsh -clscale of the fine mesh,
# default 0.18, about 70 000 nodes; empty to skip).
# Exit status: 0 when every asserted difference is within its tolerance, 1 otherwise.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="${OUT:-$HERE/out}"
FINE_CLSCALE="${FINE_CLSCALE-0.18}"

for tool in getdp gmsh python3; do
  command -v "$tool" > /dev/null || { echo "run.sh: '$tool' not found (apt-get install getdp gmsh python3)" >&2; exit 2; }
done

if [[ -z "${MRBRAKE:-}" ]]; then
  (cd "$ROOT" && cargo build --release -q -p mrbrake-cli)
  MRBRAKE="${CARGO_TARGET_DIR:-$ROOT/target}/release/mrbrake"
fi

mkdir -p "$OUT"
TIMINGS="$OUT/timings.txt"
: > "$TIMINGS"
STATUS=0

# The pot core of examples/fem/potcore.toml: 500 turns at 2 A over the 11 mm x 26 mm coil window.
TURNS=500
CURRENT_A=2.0
# A second, saturating current: |B| reaches about 2.3 T in the core.
SATURATING_CURRENT_A=12.0
current_density() { python3 -c "print($TURNS * $1 / (11e-3 * 26e-3))"; }

now() { date +%s.%N; }
elapsed() { python3 -c "print(f'{$2 - $1:.3f}')"; }

# mrbrake's vacuum permeability (CODATA 2018; GetDP's files default to 4 pi 1e-7, which differs by
# 5.45e-10 relative and would show as that uniform offset in every linear comparison).
MU_0=1.25663706212e-6

# Shared inputs: the steel B-H points exactly as mrbrake's library has them.
"$MRBRAKE" materials show steel-1010 --json > "$OUT/steel-1010.json"
python3 "$HERE/make_inputs.py" steel-table "$OUT/steel-1010.json" "$OUT/steel_nu.pro" --dense "$OUT/steel_dense.csv"
python3 "$HERE/make_inputs.py" steel-table "$OUT/steel_dense.csv" "$OUT/steel_dense_nu.pro"

# mrbrake_solve NAME MESH MATERIAL BOUNDARY [CURRENT_A]: problem file, timed JSON solve, then the
# VTU (untimed).
mrbrake_solve() {
  local name=$1 mesh=$2 material=$3 boundary=$4 current=${5:-$CURRENT_A}
  python3 "$HERE/make_inputs.py" problem "$OUT/$name.toml" "$(basename "$mesh")" "$material" "$boundary" "$TURNS" "$current"
  local t0 t1
  t0=$(now)
  "$MRBRAKE" fem solve "$OUT/$name.toml" --json > "$OUT/$name.json"
  t1=$(now)
  local internal
  internal=$(python3 -c "import json; d=json.load(open('$OUT/$name.json')); t=d['timings_s']; print(f\"{d['nodes']} nodes, internal total {t['total']:.3f} s (read {t['read']:.3f}, assemble {t['assemble']:.3f}, solve {t['solve']:.3f}, post {t['post']:.3f}), {d['newton_iterations']} Newton iterations\")")
  echo "mrbrake  $name: wall $(elapsed "$t0" "$t1") s; $internal" >> "$TIMINGS"
  "$MRBRAKE" fem solve "$OUT/$name.toml" --json --vtu "$OUT/$name.vtu" > /dev/null
}

# getdp_solve NAME MESH PRO CURRENT_A [-setnumber ...]: timed resolution, then the post-processing
# (untimed).
getdp_solve() {
  local name=$1 mesh=$2 pro=$3 current=$4
  shift 4
  local dir="$OUT/getdp_$name"
  mkdir -p "$dir"
  local args=(-msh "$mesh" -name "$dir/sol" -setnumber CurrentDensity "$(current_density "$current")"
              -setnumber CoilTurns "$TURNS"
              -setnumber Mu0 "$MU_0" -setstring OutDir "$dir" "$@")
  local t0 t1
  t0=$(now)
  getdp "$HERE/$pro" -solve Solve "${args[@]}" -v 3 > "$dir/solve.log" 2>&1
  t1=$(now)
  local iterations
  iterations=$(grep -o 'converged ([0-9]* iterations' "$dir/solve.log" | grep -o '[0-9]*' || echo 1)
  echo "GetDP    $name ($pro): wall $(elapsed "$t0" "$t1") s (resolution only), $iterations Newton iterations" >> "$TIMINGS"
  getdp "$HERE/$pro" -pos Report -res "$dir/sol.res" "${args[@]}" -v 2 > "$dir/post.log" 2>&1
}

# compare LABEL MESH MRBRAKE_CASE GETDP_CASE TOL_INTEGRAL TOL_PROBE TOL_NODAL
compare() {
  local nodal=()
  [[ -n "$7" ]] && nodal=(--tol-nodal "$7")
  python3 "$HERE/compare.py" --label "$1" --mesh "$2" --mrbrake-json "$OUT/$3.json" \
    --mrbrake-vtu "$OUT/$3.vtu" --getdp-dir "$OUT/getdp_$4" --turns "$TURNS" \
    --tol-integral "$5" --tol-probe "$6" "${nodal[@]}" || STATUS=1
}

# run_cases TAG MESH SQU_TOL: every comparison on one mesh.
run_cases() {
  local tag=$1 mesh=$2 squ_tol=$3
  local steel="$OUT/steel_nu.pro" dense="$OUT/steel_dense_nu.pro"
  mrbrake_solve "lin_$tag" "$mesh" mu_r=1000 open
  mrbrake_solve "lind_$tag" "$mesh" mu_r=1000 dirichlet
  mrbrake_solve "nl_$tag" "$mesh" steel-1010 open
  mrbrake_solve "nldense_$tag" "$mesh" csv=steel_dense.csv open
  mrbrake_solve "sat_$tag" "$mesh" steel-1010 open "$SATURATING_CURRENT_A"
  getdp_solve "p1_lin_$tag" "$mesh" axi_aphi_p1.pro "$CURRENT_A" -setstring SteelTable "$steel"
  getdp_solve "p1_lind_$tag" "$mesh" axi_aphi_p1.pro "$CURRENT_A" -setstring SteelTable "$steel" -setnumber OpenBoundary 0
  getdp_solve "p1_nl_$tag" "$mesh" axi_aphi_p1.pro "$CURRENT_A" -setstring SteelTable "$steel" -setnumber NonLinear 1
  getdp_solve "p1_nldense_$tag" "$mesh" axi_aphi_p1.pro "$CURRENT_A" -setstring SteelTable "$dense" -setnumber NonLinear 1 -setnumber Interp 0
  getdp_solve "squ_lin_$tag" "$mesh" axi_aphi_squ.pro "$CURRENT_A" -setstring SteelTable "$steel"
  getdp_solve "squ_nl_$tag" "$mesh" axi_aphi_squ.pro "$CURRENT_A" -setstring SteelTable "$steel" -setnumber NonLinear 1
  getdp_solve "p1_sat_$tag" "$mesh" axi_aphi_p1.pro "$SATURATING_CURRENT_A" -setstring SteelTable "$steel" -setnumber NonLinear 1
  getdp_solve "squ_sat_$tag" "$mesh" axi_aphi_squ.pro "$SATURATING_CURRENT_A" -setstring SteelTable "$steel" -setnumber NonLinear 1
  compare "[$tag] linear mu_r=1000, open boundary, same discrete space" "$mesh" "lin_$tag" "p1_lin_$tag" 1e-9 1e-9 1e-9
  compare "[$tag] linear mu_r=1000, A=0 on the outer circle, same discrete space" "$mesh" "lind_$tag" "p1_lind_$tag" 1e-9 1e-9 1e-9
  compare "[$tag] non-linear, dense piecewise-linear B-H table, same discrete space" "$mesh" "nldense_$tag" "p1_nldense_$tag" 1e-5 1e-5 ""
  compare "[$tag] non-linear steel-1010 (mrbrake Steffen H(B)) vs GetDP Akima nu(B^2), same space" "$mesh" "nl_$tag" "p1_nl_$tag" 1e-3 1e-3 ""
  compare "[$tag] linear, GetDP VolAxiSqu formulation (different discrete space)" "$mesh" "lin_$tag" "squ_lin_$tag" "$squ_tol" "$squ_tol" ""
  compare "[$tag] non-linear steel-1010, GetDP VolAxiSqu + Akima (different space and curve)" "$mesh" "nl_$tag" "squ_nl_$tag" "$squ_tol" "$squ_tol" ""
  compare "[$tag] saturating ($SATURATING_CURRENT_A A) steel-1010 vs GetDP Akima, same space" "$mesh" "sat_$tag" "p1_sat_$tag" 1e-3 1e-3 ""
  compare "[$tag] saturating ($SATURATING_CURRENT_A A) steel-1010 vs GetDP VolAxiSqu + Akima" "$mesh" "sat_$tag" "squ_sat_$tag" "$squ_tol" "$squ_tol" ""
}

# 1. The committed mesh (mm), scaled to metres so both solvers read the very same file.
python3 "$HERE/make_inputs.py" scale-mesh "$ROOT/examples/fem/potcore.msh" "$OUT/potcore_m.msh" 0.001
run_cases committed "$OUT/potcore_m.msh" 5e-2

# 2. A finer mesh made by gmsh from the same .geo.
if [[ -n "$FINE_CLSCALE" ]]; then
  gmsh -2 -format msh22 -clscale "$FINE_CLSCALE" "$ROOT/examples/fem/potcore.geo" -o "$OUT/potcore_fine_mm.msh" -v 1 > /dev/null
  python3 "$HERE/make_inputs.py" scale-mesh "$OUT/potcore_fine_mm.msh" "$OUT/potcore_fine_m.msh" 0.001
  run_cases fine "$OUT/potcore_fine_m.msh" 5e-3
fi

echo
echo "== wall-clock timings (not asserted) =="
cat "$TIMINGS"
if [[ $STATUS -ne 0 ]]; then
  echo "run.sh: some differences exceed their tolerance (see the FAIL lines above)" >&2
fi
exit $STATUS
