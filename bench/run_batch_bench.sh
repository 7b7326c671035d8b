#!/bin/sh
# The batched-kernel speed-up of `eomc ensemble --batch` (issue 18) per core: a 10,000-run Monte
# Carlo on one thread, one member per kernel call against batches of 4 lanes in lock step,
# alternated REPEATS times with the load average beside each figure. Two small scenes: the damped
# oscillator (rates + − × only: the rk4 CSVs of both must be the same bytes) and the bead on the
# damped hoop (sin, cos); rk4 at step 0.01 and dopri5 at rtol 1e-10, atol 1e-12, t_end 10.
# Usage: bench/run_batch_bench.sh [EOMC] [REPEATS]   (EOMC: found or built as
# bench/find_eomc.sh says, "" for that with REPEATS; REPEATS: 3)
set -eu
. "$(dirname "$0")/find_eomc.sh"
EOMC=$(find_eomc "${1:-}")
REPEATS=${2:-3}
SCENES=$(dirname "$0")/../scenes
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
run() {  # scene vary method batch-flag -> prints runs/s
    "$EOMC" ensemble "$SCENES/$1.toml" --vary "$2" --samples 10000 --seed 1 --threads 1 --t-end 10 \
        $3 $4 --format json -o "$OUT/$1$4.csv" > "$OUT/out.json"
    sed 's/.*"runs_per_s": \([0-9.e+-]*\).*/\1/' "$OUT/out.json"
}
echo "scene method alone_runs_per_s batch_runs_per_s speed_up load_average"
for scene in damped_oscillator bead_on_hoop_damped; do
    case $scene in
        damped_oscillator) vary="w=normal(1,0.1)" ;;
        *) vary="omega=uniform(2,8)" ;;
    esac
    for method in "--integrator rk4 --step 0.01" "--integrator dopri5 --rtol 1e-10 --atol 1e-12"; do
        run "$scene" "$vary" "$method" "" > /dev/null  # compiles (or finds) the kernel
        i=0
        while [ "$i" -lt "$REPEATS" ]; do
            load=$(cut -d' ' -f1-3 /proc/loadavg)
            alone=$(run "$scene" "$vary" "$method" "")
            batch=$(run "$scene" "$vary" "$method" "--batch")
            printf '%s %s %.0f %.0f %.2f %s\n' "$scene" "$(echo "$method" | cut -d' ' -f2)" "$alone" "$batch" \
                "$(echo "$batch / $alone" | bc -l)" "$load"
            if [ "$scene" = damped_oscillator ] && [ "$(echo "$method" | cut -d' ' -f2)" = rk4 ]; then
                cmp -s "$OUT/$scene.csv" "$OUT/$scene--batch.csv" || { echo "the rk4 CSVs differ" >&2; exit 1; }
            fi
            i=$((i + 1))
        done
    done
done
echo "damped_oscillator rk4: CSVs alone and batched identical"
