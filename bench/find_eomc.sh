# Sourced by the shell bench scripts: find_eomc [PATH] prints PATH when given, else the first build
# of this tree that has eomc (the order of eomc_bench.py's find_eomc: build, build-lead,
# build-bench, build-h), else builds it into build/ (Release) first, as a clean clone needs.
find_eomc() {
    if [ -n "${1:-}" ]; then
        echo "$1"
        return
    fi
    root=$(cd "$(dirname "$0")/.." && pwd)
    for b in build build-lead build-bench build-h; do
        if [ -x "$root/$b/generator/eomc" ]; then
            echo "$root/$b/generator/eomc"
            return
        fi
    done
    echo "eomc not found: building it in $root/build" >&2
    cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >&2 &&
        cmake --build "$root/build" --target eomc -j "$(nproc)" >&2 &&
        echo "$root/build/generator/eomc"
}
