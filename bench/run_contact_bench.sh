#!/usr/bin/env bash
# The contact bench (bench/RESULTS.md, issue 16): eomc against Siconos 4.4 on the bouncing ball and
# Housner's rocking block, event-driven and Moreau–Jean, and the penalty floor against stiffness.
# Needs Siconos (Debian: libsiconos-kernel-dev, libsiconos-numerics-dev). Re-run from the repository root:
#
#   bench/run_contact_bench.sh [--record] [BUILD_DIR] [REPEATS]      (defaults: build, 5)
#
# Writes {contact_tools,contact_penalty}.{csv,md}, machine.txt and the programs' own chatter
# (Siconos prints its state when it throws, log.txt) into BUILD_DIR/bench/results/contact/, or with
# --record into the tracked bench/results/contact/ (what bench/RESULTS.md cites).
set -euo pipefail
record=0
if [ "${1:-}" = --record ]; then
  record=1
  shift
fi
build=${1:-build}
repeats=${2:-5}
results=$build/bench/results/contact
[ "$record" = 1 ] && results=bench/results/contact
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target bench_contact_siconos >/dev/null
mkdir -p "$results"
{
  echo "nproc $(nproc); cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
       "$(${CXX:-g++} --version | head -1); siconos $(dpkg-query -W -f='${Version}' libsiconos-kernel-dev 2>/dev/null || echo unknown);" \
       "load average at start $(cut -d' ' -f1-3 /proc/loadavg); repeats $repeats (median);" \
       "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
} > "$results/machine.txt"
"$build/bench/bench_contact_siconos" --repeats "$repeats" --out "$results" > "$results/log.txt" 2>&1
echo "load average at end $(cut -d' ' -f1-3 /proc/loadavg)" >> "$results/machine.txt"
cat "$results/machine.txt" "$results/contact_tools.md" "$results/contact_penalty.md"
