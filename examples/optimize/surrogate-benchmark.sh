#!/bin/sh
# The README's benchmark: the surrogate-assisted optimiser against NSGA-II on the thesis's
# requirement (thesis-requirement*.toml, default mesh), hypervolume against evaluations.
#
#   cargo build --release -p mrbrake-cli
#   examples/optimize/surrogate-benchmark.sh [OUT_DIR] [MRBRAKE]
#
# Runs NSGA-II's full 40 x 31 budget (seed 2017, the problem file's) and the surrogate with seeds
# 1 to 5, twice: as the problem file says (200 designs at most, stopping when the hypervolume
# stalls) and with the stall rule off (200 designs: the curves and the overhead at 200), one
# after the other with --jobs 2, each into its own store and output folder; then measures every
# run against common reference points and draws the curves
# (crates/mrbrake-report/examples/hypervolume_benchmark.rs). About 40 min on 2 free cores.
# NSGA2_SEEDS="2017 1 2" adds NSGA-II seeds.
set -eu
OUT=${1:-target/surrogate-benchmark}
MRBRAKE=${2:-target/release/mrbrake}
NSGA2_SEEDS=${NSGA2_SEEDS:-2017}
SURROGATE_SEEDS=${SURROGATE_SEEDS:-"1 2 3 4 5"}
DIR=$(dirname "$0")
mkdir -p "$OUT"
run() { # name problem seed
    if [ ! -f "$OUT/$1.json" ]; then
        /usr/bin/env time -f "%e s wall, %U s user" "$MRBRAKE" optimize "$2" --seed "$3" \
            --store "$OUT/$1.sqlite" --out "$OUT/$1" --jobs 2 --json \
            > "$OUT/$1.json.part" 2> "$OUT/$1.log"
        mv "$OUT/$1.json.part" "$OUT/$1.json"
    fi
}
for seed in $NSGA2_SEEDS; do run "nsga2-$seed" "$DIR/thesis-requirement.toml" "$seed"; done
for seed in $SURROGATE_SEEDS; do run "surrogate-$seed" "$DIR/thesis-requirement-surrogate.toml" "$seed"; done
# The same problem with the stall rule off (its spec by absolute path, as the copy lives in OUT).
SPEC=$(cd "$DIR/../specs" && pwd)/thesis-bidirectional.toml
sed -e "s|^spec = .*|spec = \"$SPEC\"|" -e 's/^seed = 2017$/seed = 2017\nstall_iterations = 0/' \
    "$DIR/thesis-requirement-surrogate.toml" > "$OUT/surrogate-200.toml"
for seed in $SURROGATE_SEEDS; do run "surrogate200-$seed" "$OUT/surrogate-200.toml" "$seed"; done
NSGA2=""
for seed in $NSGA2_SEEDS; do NSGA2="$NSGA2 nsga2=$OUT/nsga2-$seed"; done
STALL=""
FULL=""
for seed in $SURROGATE_SEEDS; do
    STALL="$STALL surrogate=$OUT/surrogate-$seed"
    FULL="$FULL surrogate=$OUT/surrogate200-$seed"
done
cargo build --release -q -p mrbrake-report --example hypervolume_benchmark
BENCH=target/release/examples/hypervolume_benchmark
[ -n "${CARGO_TARGET_DIR:-}" ] && BENCH=$CARGO_TARGET_DIR/release/examples/hypervolume_benchmark
echo "== the surrogate as the problem file says (stall rule on)" | tee "$OUT/summary.txt"
$BENCH "$DIR/thesis-requirement.toml" "$OUT/hypervolume-stall.svg" $NSGA2 $STALL | tee -a "$OUT/summary.txt"
echo "== the surrogate to 200 designs (stall rule off)" | tee -a "$OUT/summary.txt"
$BENCH "$DIR/thesis-requirement.toml" "$OUT/hypervolume.svg" $NSGA2 $FULL | tee -a "$OUT/summary.txt"
