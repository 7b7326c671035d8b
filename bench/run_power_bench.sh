#!/bin/sh
# Powers without libm's pow (issue 33): for each checked-in kernel whose powers changed, the header
# as committed at BASE (git show) against generated/ now, side by side in one process
# (bench/solve_timing.cpp: rates checked to agree, then rhs per call over 256 states near the initial
# one, 301 alternating ~1 ms samples per side, medians and the median of the per-pair ratio).
#
# usage: [ONLY=kernel] bench/run_power_bench.sh BASE [OUT_DIR]     (run from the repository root)
# Prints a markdown table; headers and binaries stay in OUT_DIR (default: a temporary directory).
set -eu
base=$1
out=${2:-$(mktemp -d "${TMPDIR:-/tmp}/eomc_power_bench.XXXXXX")}
mkdir -p "$out/before" "$out/after"
flags="-O2 -std=c++20 -ffp-contract=off -Iruntime/include -I/usr/include/eigen3"
echo "| kernel | pow( in the header before (any function) | rhs before, median (min) ns | rhs after, median (min) ns | before / after (paired median) | max rel. diff of rates |"
echo "|---|---:|---:|---:|---:|---:|"
for entry in leo_j2:LeoJ2 leo_drag:LeoDrag geo_equinoctial:GeoEquinoctial pleiades:Pleiades \
             foucault_pendulum:FoucaultPendulum kepler_e06:KeplerE06 relative_orbit:RelativeOrbit; do
    name=${entry%%:*}
    struct=${entry#*:}
    if [ -n "${ONLY:-}" ] && [ "$name" != "$ONLY" ]; then continue; fi
    git show "$base:generated/$name.hpp" > "$out/before/$name.hpp"
    cp "generated/$name.hpp" "$out/after/$name.hpp"
    g++ $flags -I"$out" -DBEFORE_HEADER="\"before/$name.hpp\"" -DAFTER_HEADER="\"after/$name.hpp\"" -DMODEL="$struct" \
        bench/solve_timing.cpp -o "$out/timing_$name"
    "$out/timing_$name" > "$out/$name.txt"
    value() { sed -n "s/^$1 //p" "$out/$name.txt"; }
    # pow( in rhs's own code path: every call in the header, as a rough count.
    pows=$(grep -c "pow(" "$out/before/$name.hpp" || true)
    echo "| $name | $pows | $(value before_rhs_ns) ($(value before_rhs_min_ns)) | $(value after_rhs_ns) ($(value after_rhs_min_ns)) | $(value paired_ratio)× | $(value rel_diff_rates) |"
done
