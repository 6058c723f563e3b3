#!/usr/bin/env bash
# Cross-check of mrbrake's magnetodynamics (`fem solve` with [harmonic] / [transient]) against
# GetDP on the same Gmsh mesh and the same discrete space (axi_aphi_p1_dynamics.pro): the pot core
# of examples/fem/potcore.{geo,msh} with a linear conducting steel (mu_r = 1000, 5.8 MS/m), 500
# turns at 2 A, open boundary. Optional validation (needs getdp and python3); see README.md.
#
#   validation/getdp/run_dynamics.sh
#
# Environment: MRBRAKE (an mrbrake binary; default: cargo build --release -p mrbrake-cli), OUT (work
# directory, default validation/getdp/out).
# Exit status: 0 when every asserted difference is within its tolerance, 1 otherwise.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="${OUT:-$HERE/out}"

for tool in getdp python3; do
  command -v "$tool" > /dev/null || { echo "run_dynamics.sh: '$tool' not found (apt-get install getdp python3)" >&2; exit 2; }
done
if [[ -z "${MRBRAKE:-}" ]]; then
  (cd "$ROOT" && cargo build --release -q -p mrbrake-cli)
  MRBRAKE="${CARGO_TARGET_DIR:-$ROOT/target}/release/mrbrake"
fi
mkdir -p "$OUT"

TURNS=500
CURRENT_A=2.0
SIGMA=5.8e6
MU_R=1000
MU_0=1.25663706212e-6
FREQUENCIES=(1 10 100 1000)
DT=1e-4
T_END=1e-2
J=$(python3 -c "print($TURNS * $CURRENT_A / (11e-3 * 26e-3))")
now() { date +%s.%N; }

python3 "$HERE/make_inputs.py" scale-mesh "$ROOT/examples/fem/potcore.msh" "$OUT/potcore_m.msh" 0.001
MESH="$OUT/potcore_m.msh"

# mrbrake problem files: the static pot core of make_inputs.py with a conducting steel and the
# dynamic table appended.
mrbrake_file() {
  local name=$1 table=$2
  python3 "$HERE/make_inputs.py" problem "$OUT/$name.toml" potcore_m.msh "mu_r=$MU_R" open "$TURNS" "$CURRENT_A"
  python3 - "$OUT/$name.toml" "$SIGMA" "$table" <<'EOF'
import sys
path, sigma, table = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(path).read()
text = text.replace("physical = 1\nmaterial = { mu_r = ", f"physical = 1\nconductivity_S_per_m = {sigma}\nmaterial = {{ mu_r = ", 1)
open(path, "w").write(text + "\n" + table.replace("\\n", "\n") + "\n")
EOF
}

freq_list=$(IFS=,; echo "${FREQUENCIES[*]}")
mrbrake_file harmonic "[harmonic]\\nfrequencies_Hz = [$freq_list]"
mrbrake_file transient "[transient]\\nt_end = $T_END\\ndt = $DT\\nscheme = \"euler\""

t0=$(now); "$MRBRAKE" fem solve "$OUT/harmonic.toml" --json > "$OUT/harmonic.json"; t1=$(now)
echo "mrbrake  harmonic, ${#FREQUENCIES[@]} frequencies: wall $(python3 -c "print(f'{$t1 - $t0:.3f}')") s" > "$OUT/timings_dynamics.txt"
t0=$(now); "$MRBRAKE" fem solve "$OUT/transient.toml" --json > "$OUT/transient.json"; t1=$(now)
echo "mrbrake  transient, implicit Euler, $(python3 -c "print(round($T_END / $DT))") steps: wall $(python3 -c "print(f'{$t1 - $t0:.3f}')") s" >> "$OUT/timings_dynamics.txt"

common=(-msh "$MESH" -setnumber CurrentDensity "$J" -setnumber CoilTurns "$TURNS" -setnumber MuR "$MU_R"
        -setnumber Sigma "$SIGMA" -setnumber Mu0 "$MU_0")
total=0
for f in "${FREQUENCIES[@]}"; do
  dir="$OUT/getdp_harmonic_$f"
  mkdir -p "$dir"
  t0=$(now)
  getdp "$HERE/axi_aphi_p1_dynamics.pro" -solve Harmonic -name "$dir/sol" "${common[@]}" -setnumber Freq "$f" -setstring OutDir "$dir" -v 2 > "$dir/solve.log" 2>&1
  t1=$(now)
  total=$(python3 -c "print($total + $t1 - $t0)")
  getdp "$HERE/axi_aphi_p1_dynamics.pro" -pos HarmonicReport -res "$dir/sol.res" -name "$dir/sol" "${common[@]}" -setnumber Freq "$f" -setstring OutDir "$dir" -v 2 > "$dir/post.log" 2>&1
done
echo "GetDP    harmonic, ${#FREQUENCIES[@]} frequencies (one resolution each): wall $(python3 -c "print(f'{$total:.3f}')") s" >> "$OUT/timings_dynamics.txt"
dir="$OUT/getdp_transient"
mkdir -p "$dir"
t0=$(now)
getdp "$HERE/axi_aphi_p1_dynamics.pro" -solve Transient -name "$dir/sol" "${common[@]}" -setnumber StepSize "$DT" -setnumber EndTime "$T_END" -setstring OutDir "$dir" -v 2 > "$dir/solve.log" 2>&1
t1=$(now)
echo "GetDP    transient, implicit Euler (theta = 1): wall $(python3 -c "print(f'{$t1 - $t0:.3f}')") s" >> "$OUT/timings_dynamics.txt"
getdp "$HERE/axi_aphi_p1_dynamics.pro" -pos TransientReport -res "$dir/sol.res" -name "$dir/sol" "${common[@]}" -setnumber StepSize "$DT" -setnumber EndTime "$T_END" -setstring OutDir "$dir" -v 2 > "$dir/post.log" 2>&1

STATUS=0
python3 "$HERE/compare_dynamics.py" "$OUT" "$TURNS" "${FREQUENCIES[@]}" || STATUS=1
echo
echo "== wall-clock timings (not asserted) =="
cat "$OUT/timings_dynamics.txt"
exit $STATUS
