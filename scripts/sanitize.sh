#!/usr/bin/env bash
# The test suite built with AddressSanitizer and UndefinedBehaviorSanitizer, in
# ./build-sanitize (set up as scripts/setup.sh does). Arguments:
#   scripts/sanitize.sh                              every test
#   scripts/sanitize.sh --targets "A B" -R 'regex'   build only targets A B, run the tests ctest -R selects
set -euo pipefail
cd "$(dirname "$0")/.."
targets=()
if [ "${1:-}" = "--targets" ]; then
  read -r -a targets <<< "$2"
  shift 2
fi
scripts/setup.sh eomc >/dev/null
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEOMC_SANITIZE=ON "${launcher[@]}" >/dev/null
if ((${#targets[@]})); then
  cmake --build build-sanitize -j"$(nproc)" --target "${targets[@]}"
else
  cmake --build build-sanitize -j"$(nproc)"
fi
# CLN allocates its tables once at start-up and never frees them (scripts/lsan.supp).
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" "$@"
