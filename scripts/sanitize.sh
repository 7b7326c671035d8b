#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer, in
# ./build-sanitize (set up as scripts/setup.sh does). Extra arguments go to ctest, e.g.
#   scripts/sanitize.sh -R 'scene|codegen'
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEOMC_SANITIZE=ON "${launcher[@]}" >/dev/null
cmake --build build-sanitize -j"$(nproc)"
# CLN allocates its tables once at start-up and never frees them (scripts/lsan.supp).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" "$@"
