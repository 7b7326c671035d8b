#!/usr/bin/env bash
# Rigid-body formulations: what accuracy costs (bench/RESULTS.md). Every formulation the generator
# builds (euler_poisson, quaternion, euler_angles, andoyer_deprit) on Kovalevskaya's top over
# t = 5 and t = 100, and on a free body near the separatrix (the Dzhanibekov effect) over
# t = 200, each judged by (ω, γ) at t_end against a float128 Euler–Poisson run and by the drift
# of its energy. Re-run from the repository root after new formulations land:
#
#   bench/run_rigid_formulations.sh [EOMC]        (default: build/generator/eomc)
#
# Writes bench/results/rigid_formulations/<run>/{work_precision.csv,work_precision.png,
# table.txt} and machine.txt. The float128 references are cached with the compiled drivers
# (~/.cache/eomc, or $EOMC_BENCH_CACHE).
set -euo pipefail
eomc=${1:-build/generator/eomc}
cache=${EOMC_BENCH_CACHE:-}
results=bench/results/rigid_formulations
mkdir -p "$results"
{
  echo "nproc $(nproc); cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //');" \
       "$(${CXX:-g++} --version | head -1); load average at start $(cut -d' ' -f1-3 /proc/loadavg);" \
       "eomc $("$eomc" --version); commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
} > "$results/machine.txt"
cat "$results/machine.txt"
run() {  # run NAME SCENE T_END
  local out=$results/$1
  mkdir -p "$out"
  echo "== $1: $eomc bench $2 --t-end $3 -o $out"
  "$eomc" bench "$2" --t-end "$3" -o "$out" ${cache:+--cache-dir "$cache"} | tee "$out/table.txt"
}
run kovalevskaya_t5 scenes/kovalevskaya_top.toml 5
run kovalevskaya_t100 scenes/kovalevskaya_top.toml 100
run dzhanibekov_t200 scenes/dzhanibekov.toml 200
