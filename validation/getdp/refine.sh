#!/usr/bin/env bash
# Mesh-refinement study behind the VolAxiSqu tolerances of run.sh: the linear pot core (mu_r = 1000,
# open boundary) meshed by gmsh from examples/fem/potcore.geo at several -clscale values, solved by
# mrbrake (A_phi linear in (r, z)), by GetDP in the same discrete space (axi_aphi_p1.pro) and by
# GetDP's VolAxiSqu formulation (r*A_phi linear in (r^2, z), axi_aphi_squ.pro).
# The two discretisations must approach the same limit; their difference must shrink with h.
#
#   validation/getdp/refine.sh                  # clscale 1 0.5 0.25 0.125 (up to ~143 000 nodes)
#   CLSCALES="1 0.5 0.25" validation/getdp/refine.sh
#
# Environment: MRBRAKE, OUT as in run.sh. Prints tables; asserts nothing (see README.md).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="${OUT:-$HERE/out}/refine"
CLSCALES="${CLSCALES:-1 0.5 0.25 0.125}"

for tool in getdp gmsh python3; do
  command -v "$tool" > /dev/null || { echo "refine.sh: '$tool' not found" >&2; exit 2; }
done
if [[ -z "${MRBRAKE:-}" ]]; then
  (cd "$ROOT" && cargo build --release -q -p mrbrake-cli)
  MRBRAKE="${CARGO_TARGET_DIR:-$ROOT/target}/release/mrbrake"
fi
mkdir -p "$OUT"
TURNS=500
CURRENT_A=2.0
MU_0=1.25663706212e-6  # mrbrake's value (CODATA 2018)
J=$(python3 -c "print($TURNS * $CURRENT_A / (11e-3 * 26e-3))")
"$MRBRAKE" materials show steel-1010 --json > "$OUT/steel-1010.json"
python3 "$HERE/make_inputs.py" steel-table "$OUT/steel-1010.json" "$OUT/steel_nu.pro"

: > "$OUT/table.txt"
printf "%-8s %8s %16s %16s %16s %10s\n" clscale nodes "lambda mrbrake" "lambda GetDP P1" "lambda GetDP Squ" "Squ/mrb-1"
for s in $CLSCALES; do
  gmsh -2 -format msh22 -clscale "$s" "$ROOT/examples/fem/potcore.geo" -o "$OUT/mm_$s.msh" -v 1 > /dev/null
  python3 "$HERE/make_inputs.py" scale-mesh "$OUT/mm_$s.msh" "$OUT/m_$s.msh" 0.001
  python3 "$HERE/make_inputs.py" problem "$OUT/lin_$s.toml" "m_$s.msh" mu_r=1000 open "$TURNS" "$CURRENT_A"
  "$MRBRAKE" fem solve "$OUT/lin_$s.toml" --json > "$OUT/lin_$s.json"
  for pro in p1 squ; do
    mkdir -p "$OUT/${pro}_$s"
    getdp "$HERE/axi_aphi_$pro.pro" -solve Solve -msh "$OUT/m_$s.msh" -name "$OUT/${pro}_$s/sol" \
      -setnumber CurrentDensity "$J" -setnumber CoilTurns "$TURNS" -setnumber Mu0 "$MU_0" \
      -setstring SteelTable "$OUT/steel_nu.pro" -setstring OutDir "$OUT/${pro}_$s" -pos Report -v 2 \
      > "$OUT/${pro}_$s/log" 2>&1
  done
  python3 - "$OUT" "$s" "$TURNS" <<'PY'
import json, sys
out, s, turns = sys.argv[1], sys.argv[2], float(sys.argv[3])
d = json.load(open(f"{out}/lin_{s}.json"))
def lam(pro):
    a = float(open(f"{out}/{pro}_{s}/a_coil.txt").read().split()[1])
    area = float(open(f"{out}/{pro}_{s}/area_coil.txt").read().split()[1])
    return turns / area * a
m, p1, squ = d["coils"][0]["flux_linkage_Wb"], lam("p1"), lam("squ")
print(f"{s:<8} {d['nodes']:>8} {m:>16.8f} {p1:>16.8f} {squ:>16.8f} {squ / m - 1:>10.2e}")
with open(f"{out}/table.txt", "a") as f:
    f.write(f"{s} {m!r} {squ!r}\n")
PY
done

# Observed order and Richardson limit from the last three meshes (clscale ratios as given).
python3 - "$OUT/table.txt" <<'PY'
import math, sys
rows = [tuple(map(float, line.split())) for line in open(sys.argv[1])]
if len(rows) < 3:
    sys.exit(0)
(s0, m0, q0), (s1, m1, q1), (s2, m2, q2) = rows[-3:]
for k, name in ((1, "mrbrake (A_phi P1)"), (2, "GetDP VolAxiSqu")):
    a, b, c = rows[-3][k], rows[-2][k], rows[-1][k]
    p = math.log((a - b) / (b - c)) / math.log(s0 / s1)
    limit = c + (c - b) / ((s1 / s2) ** p - 1)
    print(f"{name:<20} observed order {p:.2f} (last three meshes), Richardson limit {limit:.6f} Wb")
    for row in rows:
        print(f"    clscale {row[0]:<6g} error vs that limit {(row[k] - limit) / limit:+.2e}")
PY
