#!/usr/bin/env bash
# The main job on the bundled default scene: set up, build, then derive (printed), generate
# the kernel, simulate (summary printed), write the trajectory CSV — all into ./out.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh eomc   # the tool alone: scripts/test.sh builds the test suite
build/generator/eomc run scenes/disk_tube_ball.toml -d out "$@"
