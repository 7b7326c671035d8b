// What a user's program compiles to call one side's rhs: the translation unit timed by
// bench/run_chain3d_bench.py for "generate + compile". Exactly one side per build:
//   -DEOMC_HEADER='"chain3d_12.hpp"' -DEOMC_MODEL=Chain3d12 [-DPROBE_JACOBIAN]
//   -DSYMPY_HEADER='"sympy_mass_forcing_12.hpp"' -DSYMPY_N=24
// eomc's kernel is a class template, so only the functions called here are instantiated;
// PROBE_JACOBIAN calls jacobian() too, so a --jacobian header pays for compiling it.
#ifdef EOMC_HEADER
#include EOMC_HEADER

using Model = eomc::models::EOMC_MODEL;

__attribute__((noinline)) void probe_rhs(const double* x, const Model::Parameters& p, double* dx) {
    Model::rhs(0.0, x, dx, p);
}
#ifdef PROBE_JACOBIAN
__attribute__((noinline)) void probe_jacobian(const double* x, const Model::Parameters& p, double* J) {
    Model::jacobian(0.0, x, J, p);
}
#endif
#else
#include <Eigen/Dense>

#include SYMPY_HEADER

// SymPy gives M and f; q̈ = M⁻¹ f by the same solve rhs_timing.cpp times it with.
__attribute__((noinline)) void probe_rhs(const double* x, const double* p, double* dx) {
    constexpr int n = SYMPY_N;
    Eigen::Matrix<double, n, n, Eigen::RowMajor> M;
    Eigen::Matrix<double, n, 1> f;
    sympy_mass_forcing(x, p, M.data(), f.data());
    for (int i = 0; i < n; ++i) dx[i] = x[n + i];
    Eigen::Map<Eigen::Matrix<double, n, 1>>(dx + n) = M.partialPivLu().solve(f);
}
#endif
