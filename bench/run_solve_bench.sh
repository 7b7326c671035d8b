#!/bin/sh
# The solve of M u̇ = f (and of M u̇ − Wᵀλ = f, W u̇ = r with constraint rows, and of
# M u̇ = f + D λ, Ā u̇ = c with programs) before and after codegen/solve_plan: for each checked-in
# kernel whose solve changed, the header as committed at BASE (git show) against generated/ now,
# side by side in one process (bench/solve_timing.cpp: rates checked to agree, then rhs per call,
# paired), and the g++ -O2 CPU time of a translation unit that includes the kernel and calls rhs
# (what a kernel costs `eomc simulate` to compile, less the adapter), before and after.
#
# usage: [ONLY=kernel] bench/run_solve_bench.sh BASE [OUT_DIR]      (run from the repository root)
# A kernel not at BASE is skipped (stderr says so); ONLY runs one kernel.
# Prints a markdown table; the headers and binaries stay in OUT_DIR (default /tmp/eomc_solve_bench).
set -eu
base=$1
out=${2:-/tmp/eomc_solve_bench}
mkdir -p "$out/before" "$out/after"
flags="-O2 -std=c++20 -ffp-contract=off -Iruntime/include -I/usr/include/eigen3"
echo "| kernel | solve now | rhs before, median (min) ns | rhs after, median (min) ns | before / after (paired median) | max rel. diff of rates | compile CPU before (s) | compile CPU after (s) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|"
# kernel:struct:the solve its banner names now (saddle-point: constraint rows, M u̇ − Wᵀλ = f, W u̇ = r;
# programs: M u̇ = f + D λ, Ā u̇ = c reduced to G λ = h)
for entry in leo_j2:LeoJ2:identity leo_drag:LeoDrag:identity damped_particle:DampedParticle:diagonal \
             free_disk_tube_ball:FreeDiskTubeBall:diagonal static_imbalance_gyroscope:StaticImbalanceGyroscope:block-diagonal \
             pendulum_cartesian:PendulumCartesian:saddle-point chaplygin_sleigh:ChaplyginSleigh:saddle-point \
             ball_on_turntable:BallOnTurntable:saddle-point knife_edge_sled_wall:KnifeEdgeSledWall:saddle-point \
             pendulum_energy_program:PendulumEnergyProgram:programs meshchersky_circle:MeshcherskyCircle:programs \
             two_link_arm:TwoLinkArm:programs middle_axis_hold:MiddleAxisHold:programs attitude_slew:AttitudeSlew:programs; do
    name=$(echo "$entry" | cut -d: -f1)
    struct=$(echo "$entry" | cut -d: -f2)
    path=$(echo "$entry" | cut -d: -f3)
    says="Solve of M u̇ = f: $path"
    [ "$path" = saddle-point ] && says="W u̇ = r is solved in straight-line code"
    [ "$path" = programs ] && says="G = Ā Y and h = c − Ā z in straight-line code"
    # The banner as one line (the emitter wraps it).
    sed -n '/^#pragma once/q; s|^// *||p' "generated/$name.hpp" | tr '\n' ' ' | grep -q "$says" || { echo "generated/$name.hpp: the banner does not say $says" >&2; exit 1; }
    if [ -n "${ONLY:-}" ] && [ "$name" != "$ONLY" ]; then continue; fi
    if ! git cat-file -e "$base:generated/$name.hpp" 2>/dev/null; then
        echo "generated/$name.hpp is not at $base: skipped" >&2
        continue
    fi
    git show "$base:generated/$name.hpp" > "$out/before/$name.hpp"
    cp "generated/$name.hpp" "$out/after/$name.hpp"
    g++ $flags -I"$out" -DBEFORE_HEADER="\"before/$name.hpp\"" -DAFTER_HEADER="\"after/$name.hpp\"" -DMODEL="$struct" \
        bench/solve_timing.cpp -o "$out/solve_timing_$name"
    "$out/solve_timing_$name" > "$out/$name.txt"
    value() { sed -n "s/^$1 //p" "$out/$name.txt"; }
    for side in before after; do
        printf '#include "%s.hpp"\ndouble call_rhs(const double* x, double* dx) {\n    eomc::models::%s::rhs(0.0, x, dx, eomc::models::%s::Parameters{});\n    return dx[0];\n}\n' \
            "$name" "$struct" "$struct" > "$out/$side/tu_$name.cpp"
        /usr/bin/time -f "%U %S" -o "$out/$side/time_$name" g++ $flags -I"$out/$side" -c "$out/$side/tu_$name.cpp" -o /dev/null
    done
    cpu() { awk '{printf "%.2f", $1 + $2}' "$out/$1/time_$name"; }
    echo "| $name | $path | $(value before_rhs_ns) ($(value before_rhs_min_ns)) | $(value after_rhs_ns) ($(value after_rhs_min_ns)) | $(value paired_ratio)× | $(value rel_diff_rates) | $(cpu before) | $(cpu after) |"
done
