#!/bin/sh
# The first `eomc simulate` of a scene from an empty kernel cache (generate, compile the kernel and
# its C adapter, load, run), CPU time (user + sys, /usr/bin/time) of two eomc executables,
# interleaved run by run (the load of a shared machine changes between runs), medians.
#
# usage: bench/run_cold_start_bench.sh BEFORE_EOMC AFTER_EOMC [SCENE] [REPS] [-- simulate options]
#   e.g. bench/run_cold_start_bench.sh /tmp/eomc_main build/generator/eomc scenes/leo_j2.toml 7
# Each run gets a fresh --cache-dir under a temporary directory, removed afterwards.
set -eu
before=$1
after=$2
scene=${3:-scenes/leo_j2.toml}
reps=${4:-7}
shift $(( $# < 4 ? $# : 4 ))
[ "${1:-}" = "--" ] && shift
work=$(mktemp -d "${TMPDIR:-/tmp}/eomc_cold_start.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM
for i in $(seq "$reps"); do
    for side in before after; do
        eval exe=\$$side
        rm -rf "$work/cache"
        /usr/bin/time -f "%U %S" -o "$work/time" "$exe" simulate "$scene" --t-end 1 --cache-dir "$work/cache" "$@" > /dev/null
        awk -v side="$side" '{printf "%s %.3f\n", side, $1 + $2}' "$work/time" >> "$work/all"
    done
done
median() { grep "^$1 " "$work/all" | awk '{print $2}' | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
echo "scene $scene, $reps runs each, interleaved"
echo "before: $(grep '^before ' "$work/all" | awk '{printf "%s ", $2}')s CPU, median $(median before) s"
echo "after:  $(grep '^after ' "$work/all" | awk '{printf "%s ", $2}')s CPU, median $(median after) s"
