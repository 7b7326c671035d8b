#!/usr/bin/env bash
# Fuzzes the scene reader and the expression parser with libFuzzer (clang, ASan, UBSan) for
# SECONDS each (default 60), seeded with every scene in the repository and the expressions in
# them. Exit 0 only if neither target found anything (a crash, undefined behaviour, an
# exception other than InputError, a 10 s hang or 2 GiB of memory).
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
scripts/setup.sh eomc >/dev/null
if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends clang >/dev/null
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEOMC_FUZZ=ON \
  -DEOMC_BUILD_TESTS=OFF "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_scene fuzz_expression

# Seeds: the scenes, and each quoted string in them as an expression.
corpus=build-fuzz/corpus
mkdir -p "$corpus/scene" "$corpus/expression"
n=0
while IFS= read -r -d '' scene; do
  cp "$scene" "$corpus/scene/seed-$n.toml"
  grep -o '"[^"]*"' "$scene" | sed 's/^"//; s/"$//' | while IFS= read -r e; do
    printf '%s' "$e" > "$corpus/expression/seed-$(printf '%s' "$e" | cksum | cut -d' ' -f1)"
  done
  n=$((n + 1))
done < <(find scenes tests examples bench -name '*.toml' -print0 | sort -z)

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for target in scene expression; do
  mkdir -p "build-fuzz/findings/$target"
  start=$(date +%s)
  if build-fuzz/fuzz/fuzz_$target "$corpus/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -artifact_prefix="build-fuzz/findings/$target/" -print_final_stats=1 > "build-fuzz/fuzz_$target.log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/fuzz_$target.log" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz: $target ran clean for $(( $(date +%s) - start )) s ($runs inputs)"
  else
    echo "fuzz: $target FOUND a problem after $(( $(date +%s) - start )) s; input in build-fuzz/findings/$target/:"
    tail -40 "build-fuzz/fuzz_$target.log"
    status=1
  fi
done
exit $status
