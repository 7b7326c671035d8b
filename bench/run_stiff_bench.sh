#!/usr/bin/env bash
# The stiff bench (bench/RESULTS.md, issue 19): Van der Pol mu = 1000 through eomc's radau5, SUNDIALS
# CVODE BDF (dense direct solver, user Jacobian) and eomc's DOP853, on one generated kernel and its
# symbolic Jacobian. Needs SUNDIALS (Debian: libsundials-dev). Re-run from the repository root:
#
#   bench/run_stiff_bench.sh [--record] [BUILD_DIR] [REPEATS]      (defaults: build, 5)
#
# Writes {stiff.md,machine.txt} into BUILD_DIR/bench/results/stiff/, or with --record into the tracked
# bench/results/stiff/ (what bench/RESULTS.md cites)..
set -euo pipefail
record=0
if [ "${1:-}" = --record ]; then
  record=1
  shift
fi
build=${1:-build}
repeats=${2:-5}
results=$build/bench/results/stiff
[ "$record" = 1 ] && results=bench/results/stiff
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target bench_stiff_cvode >/dev/null
mkdir -p "$results"
{
  echo "nproc $(nproc); cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
       "$(${CXX:-g++} --version | head -1); sundials $(dpkg-query -W -f='${Version}' libsundials-dev 2>/dev/null || echo unknown);" \
       "load average at start $(cut -d' ' -f1-3 /proc/loadavg); repeats $repeats (median);" \
       "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
} > "$results/machine.txt"
"$build/bench/bench_stiff_cvode" --repeats "$repeats" --tolerances 1e-6,1e-8 > "$results/stiff.md"
echo "load average at end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$results/machine.txt"
cat "$results/machine.txt" "$results/stiff.md"
