#!/usr/bin/env bash
# Orbit formulations: what accuracy costs (bench/RESULTS.md). Every formulation the generator
# builds, over 30 days of a LEO under J2 and under J2 + drag, judged by its position at t_end
# against a float128 Cowell run. Re-run from the repository root after new formulations land:
#
#   bench/run_orbit_formulations.sh [EOMC]        (default: build/generator/eomc)
#
# Writes bench/results/orbit_formulations/<scene>/{work_precision.csv,work_precision.png,
# table.txt} and machine.txt. The float128 references take a few minutes each the first time;
# they are cached with the compiled drivers (~/.cache/eomc, or $EOMC_BENCH_CACHE).
set -euo pipefail
eomc=${1:-build/generator/eomc}
cache=${EOMC_BENCH_CACHE:-}
results=bench/results/orbit_formulations
mkdir -p "$results"
{
  echo "nproc $(nproc); cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
       "$(${CXX:-g++} --version | head -1); load average at start $(cut -d' ' -f1-3 /proc/loadavg);" \
       "eomc $("$eomc" --version); commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
} > "$results/machine.txt"
cat "$results/machine.txt"
for scene in leo_j2_30d leo_j2_drag_30d; do
  out=$results/$scene
  mkdir -p "$out"
  echo "== $scene"
  "$eomc" bench "bench/scenes/$scene.toml" -o "$out" ${cache:+--cache-dir "$cache"} | tee "$out/table.txt"
done
