#!/usr/bin/env bash
# Installs what eomc needs from Debian's packages (only what is missing), then configures
# and builds it in ./build: the given targets (scripts/quickstart.sh: eomc alone), else
# everything, the test suite included. Safe to run again: a no-op when everything is in place.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config          # toolchain (the simulate command also compiles kernels with it)
  libginac-dev libcln-dev                   # symbolic algebra, exact arithmetic
  libeigen3-dev                             # the run-time LDLT solve of M q̈ = f
  libtomlplusplus-dev libcli11-dev libfmt-dev
  libboost-test-dev                         # the test suite
  libboost-dev                              # Boost.Odeint (the bench peer), Boost.Math (the tests' elliptic integrals), header-only
  libopenmpi-dev openmpi-bin                # optional: `eomc ensemble` across ranks under mpirun (built only when found)
  gnuplot-nox                               # the plots of `eomc bench`, `sweep` and `ensemble` (optional at run time)
  libsundials-dev                           # the peers CVODE and IDA (optional: bench_stiff_cvode and bench_control_ida are built only where found)
  libsiconos-kernel-dev libsiconos-numerics-dev  # the contact bench's peer, Siconos (optional: bench_contact_siconos is built only where found)
  texlive-latex-base                        # the test that compiles `eomc derive --format latex`
  python3                                   # the tests that parse the JSON of derive, equilibria and inverse
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
if (($#)); then
  cmake --build build -j"$(nproc)" --target "$@"
else
  cmake --build build -j"$(nproc)"
fi
