#!/usr/bin/env bash
# Wall and CPU time of the static non-linear solve, mrbrake against GetDP, on one gmsh mesh of the
# pot core (issue 34: "static non-linear FEA >= 20x GetDP on the same 53 k-node mesh"). Not a
# cross-check (run.sh is): only the times, measured in one run, rounds alternating the solvers.
#
#   validation/getdp/timing.sh [ROUNDS] [MRBRAKE...]
#
# Environment: CLSCALE (gmsh -clscale, default 0.205: 53 979 nodes with gmsh 4.11), OUT (work
# directory, default validation/getdp/out/timing). Several mrbrake binaries may be given (e.g. a
# baseline and a change); default: cargo build --release -p mrbrake-cli. The case is run.sh's
# "nl": steel-1010, 500 turns x 2 A, open boundary. mrbrake: the whole `fem solve --json` process
# (read, solve, post-processing, incremental inductance) on one core (taskset -c 0,
# RAYON_NUM_THREADS=1) and with its default threads; GetDP: its `-solve` step (VolAxiSqu every
# round, the same-space P1 file in the first round only: it is slow). CPU time (user + sys) is
# printed beside the wall time: on a loaded machine it is the fairer figure.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="${OUT:-$HERE/out/timing}"
CLSCALE="${CLSCALE:-0.205}"
ROUNDS="${1:-3}"
shift || true

for tool in getdp gmsh python3 taskset; do
  command -v "$tool" > /dev/null || { echo "timing.sh: '$tool' not found" >&2; exit 2; }
done
[[ -x /usr/bin/time ]] || { echo "timing.sh: /usr/bin/time not found (apt-get install time)" >&2; exit 2; }
BINARIES=("$@")
if [[ ${#BINARIES[@]} -eq 0 ]]; then
  (cd "$ROOT" && cargo build --release -q -p mrbrake-cli)
  BINARIES=("${CARGO_TARGET_DIR:-$ROOT/target}/release/mrbrake")
fi

mkdir -p "$OUT"
cd "$OUT"
gmsh -2 -format msh22 -clscale "$CLSCALE" "$ROOT/examples/fem/potcore.geo" -o mesh_mm.msh -v 1 > /dev/null
python3 "$HERE/make_inputs.py" scale-mesh mesh_mm.msh mesh_m.msh 0.001
"${BINARIES[0]}" materials show steel-1010 --json > steel-1010.json
python3 "$HERE/make_inputs.py" steel-table steel-1010.json "$OUT/steel_nu.pro"
python3 "$HERE/make_inputs.py" problem nl.toml mesh_m.msh steel-1010 open 500 2.0
echo "mesh: gmsh -clscale $CLSCALE, $(sed -n '/\$Nodes/{n;p;q}' mesh_m.msh) nodes; load average $(cut -d' ' -f1-3 /proc/loadavg)"

DENSITY=$(python3 -c "print(500 * 2.0 / (11e-3 * 26e-3))")
# timed LABEL COMMAND...: prints the wall and CPU seconds of COMMAND (its stdout to last.out).
timed() {
  local label=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  /usr/bin/time -f "%U %S" -o cpu.txt "$@" > last.out 2>&1
  t1=$(date +%s.%N)
  local cpu
  cpu=$(awk '{print $1 + $2}' cpu.txt)
  python3 -c "print(f'{\"$label\":<44} wall {$t1 - $t0:7.3f} s  cpu {$cpu:7.3f} s')"
}

for round in $(seq 1 "$ROUNDS"); do
  for pro in axi_aphi_squ.pro axi_aphi_p1.pro; do
    [[ $pro == axi_aphi_p1.pro && $round -gt 1 ]] && continue
    mkdir -p "getdp_$pro"
    timed "round $round GetDP $pro" getdp "$HERE/$pro" -solve Solve -msh "$OUT/mesh_m.msh" \
      -name "$OUT/getdp_$pro/sol" -setnumber CurrentDensity "$DENSITY" -setnumber CoilTurns 500 \
      -setnumber Mu0 1.25663706212e-6 -setstring OutDir "$OUT/getdp_$pro" \
      -setstring SteelTable "$OUT/steel_nu.pro" -setnumber NonLinear 1 -v 3
  done
  for bin in "${BINARIES[@]}"; do
    timed "round $round $(basename "$bin") (1 core)" taskset -c 0 env RAYON_NUM_THREADS=1 "$bin" fem solve nl.toml --json
    timed "round $round $(basename "$bin") (default threads)" "$bin" fem solve nl.toml --json
  done
done
