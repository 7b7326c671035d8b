// Per-call cost of eomc's generated rhs against a SymPy rhs (sympy.ccode of the cse'd
// Kane M and f, then an Eigen PartialPivLU solve), on the same system, states and
// parameters; and the numerical agreement of the two sides' M, f and q̈.
//
// Built by bench/run_pendulum_bench.py, both sides with the same flags:
//   g++ -O2 -std=c++20 -I<runtime include> -I/usr/include/eigen3 -I<dir of the headers>
//       -DEOMC_HEADER='"pendulum_16.hpp"' -DEOMC_MODEL=Pendulum16
//       -DSYMPY_HEADER='"sympy_mass_forcing_16.hpp"'
//       [-DSYMPY_LAGRANGE_HEADER='"sympy_lagrange_mass_forcing_16.hpp"']
//       [-DANGLE_RANGE=1.2]  (states' angles in ±ANGLE_RANGE; default 3: the 3-D chain's M
//                              is singular at b_k = ±π/2, so its runs keep clear of that)
//       bench/rhs_timing.cpp
// Prints `key value` lines that the driver parses.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "paired_timing.hpp"

#include EOMC_HEADER
#include SYMPY_HEADER
#ifdef SYMPY_LAGRANGE_HEADER
#include SYMPY_LAGRANGE_HEADER
#endif

#ifndef ANGLE_RANGE
#define ANGLE_RANGE 3.0
#endif

namespace {

using Model = eomc::models::EOMC_MODEL;
constexpr int n = Model::n_coordinates;
constexpr int n_state = Model::n_state;
constexpr int n_par = Model::n_parameters;

// Parameters is an aggregate of doubles declared in parameter_names order; the names are
// checked against SymPy's list below, and a wrong order would also show in the M check.
template <std::size_t... I>
Model::Parameters make_parameters(const double* p, std::index_sequence<I...>) {
    return Model::Parameters{p[I]...};
}

// Both rhs sit behind the same non-inlined call, so neither gets hoisted into the timing
// loop differently from the other.
__attribute__((noinline)) void eomc_rhs(const double* x, const Model::Parameters& p, double* dx) {
    Model::rhs(0.0, x, dx, p);
}

__attribute__((noinline)) void sympy_rhs(const double* x, const double* p, double* dx) {
    Eigen::Matrix<double, n, n, Eigen::RowMajor> M;
    Eigen::Matrix<double, n, 1> f;
    sympy_mass_forcing(x, p, M.data(), f.data());
    for (int i = 0; i < n; ++i) dx[i] = x[n + i];
    Eigen::Map<Eigen::Matrix<double, n, 1>>(dx + n) = M.partialPivLu().solve(f);
}

// max |a - b| / max |b|: normwise, so that entries near zero do not blow the ratio up.
double relative_difference(const double* a, const double* b, int size) {
    double diff = 0, scale = 0;
    for (int i = 0; i < size; ++i) {
        diff = std::max(diff, std::abs(a[i] - b[i]));
        scale = std::max(scale, std::abs(b[i]));
    }
    return scale > 0 ? diff / scale : diff;
}

}  // namespace

int main() {
    for (int i = 0; i < n_par; ++i)
        if (std::strcmp(Model::parameter_names[i], sympy_mass_forcing_parameter_names[i]) != 0) {
            std::printf("error parameter %d: eomc %s, sympy %s\n", i, Model::parameter_names[i],
                        sympy_mass_forcing_parameter_names[i]);
            return 1;
        }

    // Fixed seed: the same states every run. Parameters away from the scene's defaults
    // (all 1) so that a swapped m_k / l_k would show.
    std::mt19937_64 rng(20240601);
    std::uniform_real_distribution<double> angle(-ANGLE_RANGE, ANGLE_RANGE), rate(-2.0, 2.0), par(0.5, 1.5);
    std::vector<double> p(n_par);
    for (double& v : p) v = par(rng);
    p[0] = 9.81;
    const Model::Parameters params = make_parameters(p.data(), std::make_index_sequence<n_par>{});

    constexpr int batch = 256;
    std::vector<double> states(std::size_t(batch) * n_state);
    for (int b = 0; b < batch; ++b)
        for (int i = 0; i < n_state; ++i) states[std::size_t(b) * n_state + i] = i < n ? angle(rng) : rate(rng);

    // Agreement over the whole batch: M and f entry by entry, then q̈.
    double err_M = 0, err_f = 0, err_rhs = 0;
#ifdef SYMPY_LAGRANGE_HEADER
    double err_lag_M = 0, err_lag_f = 0;
#endif
    for (int b = 0; b < batch; ++b) {
        const double* x = &states[std::size_t(b) * n_state];
        double Me[n * n], fe[n], Ms[n * n], fs[n], dxe[n_state], dxs[n_state];
        Model::mass_matrix(0.0, x, Me, params);
        Model::forcing(0.0, x, fe, params);
        sympy_mass_forcing(x, p.data(), Ms, fs);
        err_M = std::max(err_M, relative_difference(Ms, Me, n * n));
        err_f = std::max(err_f, relative_difference(fs, fe, n));
#ifdef SYMPY_LAGRANGE_HEADER
        double Ml[n * n], fl[n];
        sympy_lagrange_mass_forcing(x, p.data(), Ml, fl);
        err_lag_M = std::max(err_lag_M, relative_difference(Ml, Me, n * n));
        err_lag_f = std::max(err_lag_f, relative_difference(fl, fe, n));
#endif
        eomc_rhs(x, params, dxe);
        sympy_rhs(x, p.data(), dxs);
        err_rhs = std::max(err_rhs, relative_difference(dxs + n, dxe + n, n));
    }
    std::printf("rel_diff_M %.3e\nrel_diff_f %.3e\nrel_diff_qdd %.3e\n", err_M, err_f, err_rhs);
#ifdef SYMPY_LAGRANGE_HEADER
    std::printf("rel_diff_lagrange_M %.3e\nrel_diff_lagrange_f %.3e\n", err_lag_M, err_lag_f);
#endif

    // Timing: sweeps over the batch, paired (bench/paired_timing.hpp).
    double checksum_eomc = 0, checksum_sympy = 0;
    std::vector<double> out(n_state);
    auto sweep_eomc = [&] {
        for (int b = 0; b < batch; ++b) {
            eomc_rhs(&states[std::size_t(b) * n_state], params, out.data());
            checksum_eomc += out[n_state - 1];
        }
    };
    auto sweep_sympy = [&] {
        for (int b = 0; b < batch; ++b) {
            sympy_rhs(&states[std::size_t(b) * n_state], p.data(), out.data());
            checksum_sympy += out[n_state - 1];
        }
    };
    const bench::PairedTiming t = bench::time_paired(sweep_eomc, sweep_sympy, batch);
    std::printf("eomc_rhs_ns %.2f\nsympy_rhs_ns %.2f\n", 1e9 * t.first_median, 1e9 * t.second_median);
    std::printf("eomc_rhs_min_ns %.2f\nsympy_rhs_min_ns %.2f\n", 1e9 * t.first_min, 1e9 * t.second_min);
    std::printf("paired_ratio %.4f\n", 1 / t.ratio);  // SymPy / eomc
    std::printf("checksum_eomc %.17g\nchecksum_sympy %.17g\n", checksum_eomc, checksum_sympy);
    return 0;
}
