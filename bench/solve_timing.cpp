// rhs per call of one scene's kernel as two generators emitted it (BEFORE_HEADER, AFTER_HEADER):
// the solve of M u̇ = f changed, nothing else. Both kernels see the same states and parameters;
// their rates must agree to round-off before they are timed.
//
// Built by bench/run_solve_bench.sh:
//   g++ -O2 -std=c++20 -I<runtime include> -I/usr/include/eigen3
//       -DBEFORE_HEADER='"before/leo_j2.hpp"' -DAFTER_HEADER='"after/leo_j2.hpp"' -DMODEL=LeoJ2
//       bench/solve_timing.cpp
// Prints `key value` lines.
#include <array>
#include <cmath>
#include <limits>

// What either kernel may include, first: inside the namespaces below their #pragma once makes
// the kernels' own includes no-ops.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <eomc/runtime/constraint_projection.hpp>
#include <eomc/runtime/constraints.hpp>
#include <eomc/runtime/program/control.hpp>
#include <eomc/runtime/program/reduced_control.hpp>
#include <eomc/runtime/version.hpp>

#include <cstdio>
#include <random>
#include <vector>

#include "paired_timing.hpp"

// Inside these namespaces a kernel's eomc::runtime:: names the real runtime through an alias.
namespace before {
namespace eomc {
namespace runtime = ::eomc::runtime;
}
#include BEFORE_HEADER
}  // namespace before
namespace after {
namespace eomc {
namespace runtime = ::eomc::runtime;
}
#include AFTER_HEADER
}  // namespace after

namespace {

using Before = before::eomc::models::MODEL;
using After = after::eomc::models::MODEL;
static_assert(Before::n_state == After::n_state && Before::velocity_offset == After::velocity_offset);
constexpr int n_state = After::n_state;

// Behind the same non-inlined call, so that neither is hoisted into the loop differently.
template <class K>
__attribute__((noinline)) void call_rhs(const double* x, const typename K::Parameters& p, double* dx) {
    K::rhs(0.0, x, dx, p);
}

}  // namespace

int main() {
    // States around the scene's initial state, x_i = x0_i (1 + u/5) + u/5 with u in [−1, 1].
    std::mt19937_64 rng(20261126);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    constexpr int batch = 256;
    std::vector<double> states(std::size_t(batch) * n_state);
    for (int b = 0; b < batch; ++b)
        for (int i = 0; i < n_state; ++i) {
            const double v = u(rng);
            states[std::size_t(b) * n_state + i] = After::initial_state[std::size_t(i)] * (1 + v / 5) + v / 5;
        }
    const Before::Parameters pb{};
    const After::Parameters pa{};

    double diff = 0;
    std::array<double, n_state> xb, xa;
    for (int b = 0; b < batch; ++b) {
        call_rhs<Before>(&states[std::size_t(b) * n_state], pb, xb.data());
        call_rhs<After>(&states[std::size_t(b) * n_state], pa, xa.data());
        double d = 0, scale = 0;
        for (int i = 0; i < n_state; ++i) {
            d = std::max(d, std::abs(xa[std::size_t(i)] - xb[std::size_t(i)]));
            scale = std::max(scale, std::abs(xb[std::size_t(i)]));
        }
        diff = std::max(diff, scale > 0 ? d / scale : d);
    }
    std::printf("rel_diff_rates %.3e\n", diff);

    // Sweeps over the batch, paired (bench/paired_timing.hpp).
    double checksum = 0;
    auto sweep = [&](auto&& one) {
        for (int b = 0; b < batch; ++b) {
            one(&states[std::size_t(b) * n_state]);
            checksum += xa[n_state - 1];
        }
    };
    auto sweep_before = [&] { sweep([&](const double* x) { call_rhs<Before>(x, pb, xa.data()); }); };
    auto sweep_after = [&] { sweep([&](const double* x) { call_rhs<After>(x, pa, xa.data()); }); };
    const bench::PairedTiming t = bench::time_paired(sweep_before, sweep_after, batch);
    std::printf("before_rhs_ns %.1f\nafter_rhs_ns %.1f\nbefore_rhs_min_ns %.1f\nafter_rhs_min_ns %.1f\n"
                "paired_ratio %.3f\nchecksum %.6e\n",
                t.first_median * 1e9, t.second_median * 1e9, t.first_min * 1e9, t.second_min * 1e9, t.ratio, checksum);
}
