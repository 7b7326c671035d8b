#!/bin/sh
# Throughput of `eomc ensemble` (issue 18): a 10,000-run Monte Carlo of a small scene on 1 and 2
# threads, alternated REPEATS times (a shared machine's load moves single runs), with the load
# average beside each figure; the CSVs of the two thread counts must be the same bytes. With
# mpirun on PATH (and eomc built with MPI), the same for 1 and 2 ranks of one thread each.
# Usage: bench/run_ensemble_bench.sh [EOMC] [REPEATS]   (EOMC: found or built as
# bench/find_eomc.sh says, "" for that with REPEATS; REPEATS: 3)
set -eu
. "$(dirname "$0")/find_eomc.sh"
EOMC=$(find_eomc "${1:-}")
REPEATS=${2:-3}
SCENE=$(dirname "$0")/../scenes/damped_oscillator.toml
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
ARGS="ensemble $SCENE --vary w=normal(1,0.1) --vary x=uniform(0.5,1.5) --samples 10000 --seed 1 --format json"
"$EOMC" $ARGS --threads 1 -o "$OUT/warm.csv" > /dev/null   # compiles (or finds) the kernel
echo "threads runs_per_s wall_s load_average"
i=0
while [ "$i" -lt "$REPEATS" ]; do
    for t in 1 2; do
        load=$(cut -d' ' -f1-3 /proc/loadavg)
        "$EOMC" $ARGS --threads "$t" -o "$OUT/t$t.csv" > "$OUT/t$t.json"
        rate=$(sed 's/.*"runs_per_s": \([0-9.e+-]*\).*/\1/' "$OUT/t$t.json")
        wall=$(sed 's/.*"wall_s": \([0-9.e+-]*\).*/\1/' "$OUT/t$t.json")
        printf '%s %.0f %.3f %s\n' "$t" "$rate" "$wall" "$load"
    done
    cmp -s "$OUT/t1.csv" "$OUT/t2.csv" || { echo "the CSVs of 1 and 2 threads differ" >&2; exit 1; }
    i=$((i + 1))
done
echo "CSVs of 1 and 2 threads: identical ($(wc -l < "$OUT/t1.csv") lines)"
command -v mpirun > /dev/null || exit 0
# Open MPI refuses root unless told (containers, CI).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "ranks runs_per_s wall_s load_average   (1 thread per rank; wall: the slowest rank's runs)"
i=0
while [ "$i" -lt "$REPEATS" ]; do
    for n in 1 2; do
        load=$(cut -d' ' -f1-3 /proc/loadavg)
        mpirun -np "$n" --oversubscribe "$EOMC" $ARGS --threads 1 -o "$OUT/r$n.csv" > "$OUT/r$n.json"
        rate=$(sed 's/.*"runs_per_s": \([0-9.e+-]*\).*/\1/' "$OUT/r$n.json")
        wall=$(sed 's/.*"wall_s": \([0-9.e+-]*\).*/\1/' "$OUT/r$n.json")
        printf '%s %.0f %.3f %s\n' "$n" "$rate" "$wall" "$load"
    done
    cmp -s "$OUT/t1.csv" "$OUT/r2.csv" || { echo "the CSVs of 1 thread and 2 ranks differ" >&2; exit 1; }
    i=$((i + 1))
done
echo "CSVs of 1 process and 2 ranks: identical"
