// The stiff bench (bench/RESULTS.md, issue 19): Van der Pol at mu = 1000 from (2, 0) over
// [0, 3000] through eomc's radau5, SUNDIALS CVODE's BDF (variable order 1-5, Newton with the dense
// direct linear solver and a user Jacobian) and eomc's DOP853, all on the same generated kernel
// (generated/van_der_pol_stiff.hpp) and the two implicit ones on its same symbolic Jacobian.
// For each method and rtol = atol: wall time (median of repeats), system calls, Jacobian calls,
// steps, and the max-norm error of the final state against a reference: radau5 in long double at
// rtol = atol = 1e-16, checked against one at 1e-14 (their difference bounds its error).
//
//   bench_stiff_cvode [--repeats N] [--tolerances 1e-6,1e-8]      (markdown table on stdout)

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/radau5.hpp"
#include "van_der_pol_stiff.hpp"

namespace rt = eomc::runtime;
using K = eomc::models::VanDerPolStiff;

namespace {

constexpr double t_end = 3000.0;
constexpr int n = K::n_state;
const K::Parameters parameters{};

struct Run {
  std::string method;
  double tol = 0, seconds = 0, error = 0;
  std::size_t rhs = 0, jacobians = 0, steps = 0, rejected = 0;
  std::array<double, n> x{};
};

// The kernel as a runtime system, counting every call (the initial step's included), with its Jacobian (row-major) for radau5.
template <class S>
struct KernelSystem {
  std::size_t* rhs;
  std::size_t* jacobians;
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    ++*rhs;
    K::rhs<S>(t, x.data(), dxdt.data(), parameters);
  }
  void jacobian(S t, const rt::State<S>& x, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) const {
    ++*jacobians;
    std::array<S, n * n> out{};
    K::jacobian<S>(t, x.data(), out.data(), parameters);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) J(i, j) = out[std::size_t(i * n + j)];
  }
};

Run radau5(double tol) {
  Run r{"eomc radau5", tol};
  KernelSystem<double> sys{&r.rhs, &r.jacobians};
  rt::Radau5<double> st;
  rt::State<double> x(K::initial_state.begin(), K::initial_state.end());
  const rt::Stats s = rt::integrate_adaptive(st, sys, x, 0.0, t_end, 0.0, rt::Tolerances{tol, tol},
                                             [](double, const rt::State<double>&) {});
  r.steps = s.accepted;
  r.rejected = s.rejected;
  std::copy(x.begin(), x.end(), r.x.begin());
  return r;
}

Run dop853(double tol) {
  Run r{"eomc dop853", tol};
  KernelSystem<double> sys{&r.rhs, &r.jacobians};
  rt::Dop853<double> st(rt::Dop853<double>::default_settings(), false);
  rt::State<double> x(K::initial_state.begin(), K::initial_state.end());
  const rt::Stats s = rt::integrate_adaptive(st, sys, x, 0.0, t_end, 0.0, rt::Tolerances{tol, tol},
                                             [](double, const rt::State<double>&) {});
  r.steps = s.accepted;
  r.rejected = s.rejected;
  std::copy(x.begin(), x.end(), r.x.begin());
  return r;
}

// CVODE's callbacks over the same kernel.
struct CvodeCounts {
  std::size_t rhs = 0, jacobians = 0;
};

int cvode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user) {
  ++static_cast<CvodeCounts*>(user)->rhs;
  K::rhs<double>(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), parameters);
  return 0;
}

int cvode_jacobian(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector, N_Vector) {
  ++static_cast<CvodeCounts*>(user)->jacobians;
  std::array<double, n * n> out{};
  K::jacobian<double>(t, N_VGetArrayPointer(y), out.data(), parameters);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) SM_ELEMENT_D(J, i, j) = out[std::size_t(i * n + j)];
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed with flag " + std::to_string(flag));
}

Run cvode_bdf(double tol) {
  Run r{"CVODE BDF", tol};
  CvodeCounts counts;
  SUNContext ctx = nullptr;
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  N_Vector y = N_VNew_Serial(n, ctx);
  for (int i = 0; i < n; ++i) NV_Ith_S(y, i) = K::initial_state[std::size_t(i)];
  void* mem = CVodeCreate(CV_BDF, ctx);
  check(CVodeInit(mem, cvode_rhs, 0.0, y), "CVodeInit");
  check(CVodeSetUserData(mem, &counts), "CVodeSetUserData");
  check(CVodeSStolerances(mem, tol, tol), "CVodeSStolerances");
  SUNMatrix A = SUNDenseMatrix(n, n, ctx);
  SUNLinearSolver LS = SUNLinSol_Dense(y, A, ctx);
  check(CVodeSetLinearSolver(mem, LS, A), "CVodeSetLinearSolver");
  check(CVodeSetJacFn(mem, cvode_jacobian), "CVodeSetJacFn");
  check(CVodeSetMaxNumSteps(mem, 10'000'000), "CVodeSetMaxNumSteps");
  check(CVodeSetStopTime(mem, t_end), "CVodeSetStopTime");
  sunrealtype t = 0.0;
  check(CVode(mem, t_end, y, &t, CV_NORMAL), "CVode");
  long steps = 0, fails = 0;
  CVodeGetNumSteps(mem, &steps);
  CVodeGetNumErrTestFails(mem, &fails);
  r.rhs = counts.rhs;
  r.jacobians = counts.jacobians;
  r.steps = std::size_t(steps);
  r.rejected = std::size_t(fails);
  for (int i = 0; i < n; ++i) r.x[std::size_t(i)] = NV_Ith_S(y, i);
  SUNLinSolFree(LS);
  SUNMatDestroy(A);
  N_VDestroy(y);
  CVodeFree(&mem);
  SUNContext_Free(&ctx);
  return r;
}

// The reference: radau5 in long double.
std::array<long double, n> reference(long double tol) {
  std::size_t rhs = 0, jac = 0;
  KernelSystem<long double> sys{&rhs, &jac};
  rt::Radau5<long double> st;
  rt::State<long double> x(K::initial_state.begin(), K::initial_state.end());
  rt::integrate_adaptive(st, sys, x, 0.0L, static_cast<long double>(t_end), 0.0L, rt::Tolerances{double(tol), double(tol)},
                         [](long double, const rt::State<long double>&) {});
  return {x[0], x[1]};
}

// Median wall time over at least `repeats` runs and 0.5 s in all.
Run timed(const std::function<Run(double)>& f, double tol, int repeats) {
  Run r = f(tol);
  std::vector<double> times;
  double total = 0;
  while (int(times.size()) < repeats || total < 0.5) {
    const auto start = std::chrono::steady_clock::now();
    r = f(tol);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    total += times.back();
    if (times.size() >= 200) break;
  }
  std::sort(times.begin(), times.end());
  r.seconds = times[times.size() / 2];
  return r;
}

std::vector<double> parse_list(const char* text) {
  std::vector<double> out;
  std::string s(text);
  for (std::size_t at = 0; at <= s.size();) {
    const std::size_t comma = std::min(s.find(',', at), s.size());
    out.push_back(std::stod(s.substr(at, comma - at)));
    at = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) try {
  int repeats = 5;
  std::vector<double> tolerances{1e-6, 1e-8};
  const auto usage = [&](std::FILE* to) {
    std::fprintf(to, "usage: %s [--repeats N] [--tolerances 1e-6,1e-8]   (a markdown table on stdout)\n", argv[0]);
  };
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if (!std::strcmp(argv[i], "--repeats") && has_value) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--tolerances") && has_value) {
      tolerances = parse_list(argv[++i]);
    } else {
      usage(stderr);
      return 2;
    }
  }
  const auto ref = reference(1e-16L), check_ref = reference(1e-14L);
  const double ref_spread = double(std::max(std::fabs(ref[0] - check_ref[0]), std::fabs(ref[1] - check_ref[1])));
  std::printf("Van der Pol mu = %g from (2, 0) to t = %g; reference: radau5 in long double at rtol = atol = 1e-16, "
              "x = (%.17Lg, %.17Lg), differs from the run at 1e-14 by %.2g (an upper bound on its error)\n\n",
              parameters.mu, t_end, ref[0], ref[1], ref_spread);
  std::printf("| rtol = atol | method | time (ms) | rhs calls | Jacobians | steps | rejected | error at t_end | time / CVODE's |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (double tol : tolerances) {
    std::vector<Run> runs{timed(radau5, tol, repeats), timed(cvode_bdf, tol, repeats), timed(dop853, tol, repeats)};
    const double cvode_s = runs[1].seconds;
    for (Run& r : runs) {
      r.error = std::max(std::fabs(r.x[0] - double(ref[0])), std::fabs(r.x[1] - double(ref[1])));
      std::printf("| %.0e | %s | %.3g | %zu | %zu | %zu | %zu | %.2e | %.2f |\n", tol, r.method.c_str(), r.seconds * 1e3,
                  r.rhs, r.jacobians, r.steps, r.rejected, r.error, r.seconds / cvode_s);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_stiff_cvode: %s\n", e.what());
  return 1;
}
