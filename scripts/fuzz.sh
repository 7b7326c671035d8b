#!/usr/bin/env bash
# Fuzzes with libFuzzer (clang, ASan, UBSan): the scene reader and the expression parser for
# SECONDS each (default 60), and for half as long each the front end past the reader (small
# scenes derived, lowered and emitted) and the flags of `sweep` and `ensemble` (--grid, --vary,
# --samples, --seed, --observe). Seeded with every scene in the repository, the expressions in
# them, and the flags the tests, the docs and the scripts give. Exit 0 only if no target found
# anything (a crash, undefined behaviour, an exception other than the refusals eomc exits 2 with,
# a 10 s hang or 2 GiB of memory).
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
half=$(( seconds / 2 > 0 ? seconds / 2 : 1 ))
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
cmake --build build-fuzz -j"$(nproc)" --target fuzz_scene fuzz_expression fuzz_derive fuzz_ensemble_flags

# Seeds: the scenes (for the reader and the derivation), and each quoted string in them as an
# expression.
corpus=build-fuzz/corpus
mkdir -p "$corpus/scene" "$corpus/expression" "$corpus/derive" "$corpus/ensemble_flags"
n=0
while IFS= read -r -d '' scene; do
  cp "$scene" "$corpus/scene/seed-$n.toml"
  cp "$scene" "$corpus/derive/seed-$n.toml"
  grep -o '"[^"]*"' "$scene" | sed 's/^"//; s/"$//' | while IFS= read -r e; do
    printf '%s' "$e" > "$corpus/expression/seed-$(printf '%s' "$e" | cksum | cut -d' ' -f1)"
  done
  n=$((n + 1))
done < <(find scenes tests examples bench -name '*.toml' -print0 | sort -z)

# The ensemble flags, a line each ("--grid TEXT"): every flag alone — the parsers' calls and the
# argument pairs in the tests, the flags on the command lines of the docs and the scripts (quotes
# removed) — and the flags of each such line together.
seed_flags() {  # stdin: a flag a line → one seed
  local text
  text=$(cat)
  [ -n "$text" ] && printf '%s' "$text" > "$corpus/ensemble_flags/seed-$(printf '%s' "$text" | cksum | cut -d' ' -f1)"
  return 0
}
command_line_flags() {  # stdin: text → its flags, a line each ("--grid TEXT")
  { grep -oE -- "--(grid|vary|observe|samples|seed)[ =]('[^']*'|\"[^\"]*\"|[^ '\"\`\\]+)" || true; } |
    sed -E "s/^(--[a-z]+)[ =]/\1 /; s/ '(.*)'\$/ \1/; s/ \"(.*)\"\$/ \1/"
}
{
  grep -rhoE 'parse_(grid|variation|observation)\("[^"]*"\)' tests |
    sed -E 's/^parse_grid\("/--grid /; s/^parse_variation\("/--vary /; s/^parse_observation\("/--observe /; s/"\)$//'
  grep -rhoE '"--(grid|vary|observe|samples|seed)", *"[^"]*"' tests | sed -E 's/^"(--[a-z]+)", *"/\1 /; s/"$//'
  grep -rhI --exclude=fuzz.sh -- "--" docs README.md bench scripts examples | command_line_flags
} | sort -u | while IFS= read -r flag; do printf '%s\n' "$flag" | seed_flags; done
grep -rhIE --exclude=fuzz.sh -- "--(grid|vary|observe)" docs README.md bench scripts examples tests |
  while IFS= read -r line; do
    { printf '%s\n' "$line" | command_line_flags
      { printf '%s\n' "$line" | grep -oE '"--(grid|vary|observe|samples|seed)", *"[^"]*"' || true; } | sed -E 's/^"(--[a-z]+)", *"/\1 /; s/"$//'
    } | seed_flags
  done

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for target in scene expression derive ensemble_flags; do
  mkdir -p "build-fuzz/findings/$target"
  start=$(date +%s)
  time=$seconds
  case $target in derive|ensemble_flags) time=$half ;; esac
  if build-fuzz/fuzz/fuzz_$target "$corpus/$target" -max_total_time="$time" -timeout=10 -rss_limit_mb=2048 \
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
