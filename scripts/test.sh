#!/usr/bin/env bash
# Set up and build as quickstart.sh does, then run the whole test suite (CTest over Boost.Test).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
