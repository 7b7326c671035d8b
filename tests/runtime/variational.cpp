// runtime/variational.hpp: the variational equations Φ̇ = J Φ of a kernel's ẋ = f(t, x), checked
// on linear systems ẋ = A x, whose state-transition matrix is Φ(t) = e^{At} in closed form
// (Hairer, Nørsett, Wanner I, Sect. I.14):
//   * the harmonic oscillator, A = [[0, 1], [−ω², 0]]: the rates at Φ = e^{At} are d/dt e^{At},
//     and RK4 on y = (x, Φ) converges to e^{At} at the method's order 4;
//   * a diagonal system of 65 states (65² > 4096: J on the heap), Φ = diag(e^{λ_i t}).
#define BOOST_TEST_MODULE runtime_variational
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/kernel.hpp"
#include "eomc/runtime/runtime.hpp"
#include "eomc/runtime/variational.hpp"

namespace {

namespace rt = eomc::runtime;
const double eps = std::numeric_limits<double>::epsilon();

// ẍ = −ω² x as a kernel.
struct Oscillator {
  static constexpr int n_coordinates = 1;
  static constexpr int n_state = 2;
  static constexpr int n_parameters = 1;
  static constexpr int n_invariants = 1;
  static constexpr const char* scene_name = "oscillator";
  static constexpr std::array<const char*, n_state> state_names{"x", "x_dot"};
  static constexpr std::array<const char*, n_parameters> parameter_names{"omega"};
  static constexpr std::array<const char*, n_invariants> invariant_names{"energy"};
  static constexpr std::array<double, n_state> initial_state{1, 0};
  struct Parameters {
    double omega = 1.7;
  };
  template <class S>
  static void rhs(S, const S* x, S* dxdt, const Parameters& p) {
    dxdt[0] = x[1];
    dxdt[1] = -S(p.omega) * S(p.omega) * x[0];
  }
  template <class S>
  static void jacobian(S, const S*, S* out, const Parameters& p) {
    out[0] = S(0);
    out[1] = S(1);
    out[2] = -S(p.omega) * S(p.omega);
    out[3] = S(0);
  }
  template <class S>
  static void invariants(S, const S* x, S* out, const Parameters& p) {
    out[0] = (x[1] * x[1] + S(p.omega) * S(p.omega) * x[0] * x[0]) / S(2);
  }
};
static_assert(rt::KernelWithJacobian<Oscillator>);

// e^{At} of the oscillator, row-major.
std::array<double, 4> oscillator_phi(double t, double w) {
  const double c = std::cos(w * t), s = std::sin(w * t);
  return {c, s / w, -w * s, c};
}

// ẋ_i = λ_i x_i, λ_i = (i − 32)/16: 65 states.
struct Diagonal {
  static constexpr int n_coordinates = 65;
  static constexpr int n_state = 65;
  static constexpr int n_parameters = 0;
  static constexpr int n_invariants = 0;
  static constexpr const char* scene_name = "diagonal";
  static constexpr std::array<const char*, n_state> state_names{};
  static constexpr std::array<const char*, n_parameters> parameter_names{};
  static constexpr std::array<const char*, n_invariants> invariant_names{};
  static constexpr std::array<double, n_state> initial_state{};
  struct Parameters {};
  static constexpr double lambda(int i) { return (i - 32) / 16.0; }
  template <class S>
  static void rhs(S, const S* x, S* dxdt, const Parameters&) {
    for (int i = 0; i < n_state; ++i) dxdt[i] = S(lambda(i)) * x[i];
  }
  template <class S>
  static void jacobian(S, const S*, S* out, const Parameters&) {
    for (int i = 0; i < n_state * n_state; ++i) out[i] = S(0);
    for (int i = 0; i < n_state; ++i) out[i * n_state + i] = S(lambda(i));
  }
  template <class S>
  static void invariants(S, const S*, S*, const Parameters&) {}
};
static_assert(rt::KernelWithJacobian<Diagonal> && Diagonal::n_state * Diagonal::n_state > 4096);

}  // namespace

// At Φ = e^{At} the rates of Φ are A e^{At} = d/dt e^{At}: each entry is a sum of two products
// with one non-zero term (A has one non-zero entry per row), so it is the closed form's value
// rounded: within an ulp of ω² (the largest entry) plus the closed form's own rounding.
BOOST_AUTO_TEST_CASE(oscillator_rates_are_the_derivative_of_exp_At) {
  const Oscillator::Parameters p{};
  const double w = p.omega;
  for (double t : {0.0, 0.3, 1.0, 2.5, 10.0}) {
    const auto phi = oscillator_phi(t, w);
    std::array<double, rt::n_variational<Oscillator>> y{0.4, -0.2, phi[0], phi[1], phi[2], phi[3]}, dydt{};
    rt::variational_rhs<Oscillator>(t, y.data(), dydt.data(), p);
    const double c = std::cos(w * t), s = std::sin(w * t);
    const std::array<double, 4> derivative{-w * s, c, -w * w * c, -w * s};
    BOOST_TEST(dydt[0] == y[1]);
    BOOST_TEST(dydt[1] == -w * w * y[0]);
    for (int k = 0; k < 4; ++k) BOOST_TEST(std::abs(dydt[2 + k] - derivative[k]) <= 4 * eps * w * w, "entry " << k);
  }
}

// RK4 on y = (x, Φ) from Φ(0) = I over one period: Φ(T) → e^{AT} = I with the global error
// C h⁴; halving h divides it by 2⁴ = 16 (up to O(h) in the ratio). Wrong rates would converge
// to another matrix, with an error that does not fall.
BOOST_AUTO_TEST_CASE(integrated_phi_converges_to_exp_At_at_order_four) {
  const Oscillator::Parameters p{};
  const double T = 2 * std::acos(-1.0) / p.omega;
  auto sys = [&](double t, const rt::State<double>& y, rt::State<double>& dydt) {
    rt::variational_rhs<Oscillator>(t, y.data(), dydt.data(), p);
  };
  auto error_with = [&](int steps) {
    rt::State<double> y{1, 0, 1, 0, 0, 1};
    rt::Rk4<double> stepper;
    rt::integrate_fixed(stepper, sys, y, 0.0, T, T / steps, [](double, const rt::State<double>&) {});
    const auto exact = oscillator_phi(T, p.omega);
    double e = 0.0;
    for (int k = 0; k < 4; ++k) e = std::max(e, std::abs(y[2 + k] - exact[k]));
    // The state itself is Φ's first column applied to x(0) = (1, 0).
    BOOST_TEST(std::abs(y[0] - y[2]) <= 1e-12);
    BOOST_TEST(std::abs(y[1] - y[4]) <= 1e-12);
    return e;
  };
  const double e1 = error_with(200), e2 = error_with(400);
  BOOST_TEST_MESSAGE("|Phi(T) - exp(AT)|: " << e1 << " (200 steps), " << e2 << " (400 steps), ratio " << e1 / e2);
  BOOST_TEST(e1 / e2 > 14.0);
  BOOST_TEST(e1 / e2 < 18.0);
  BOOST_TEST(e2 < 1e-7);
}

// 65 states: J (65² entries) lives on the heap. At Φ = diag(e^{λ t}) the rates are the products
// λ_i e^{λ_i t} on the diagonal (one rounding) and exactly zero elsewhere.
BOOST_AUTO_TEST_CASE(large_kernels_take_the_heap_path) {
  constexpr int n = Diagonal::n_state;
  const double t = 0.75;
  std::vector<double> y(rt::n_variational<Diagonal>, 0.0), dydt(y.size(), 1.0);
  for (int i = 0; i < n; ++i) {
    y[i] = 1.0 + i;
    y[n + i * n + i] = std::exp(Diagonal::lambda(i) * t);
  }
  rt::variational_rhs<Diagonal>(t, y.data(), dydt.data(), Diagonal::Parameters{});
  for (int i = 0; i < n; ++i) {
    BOOST_TEST(dydt[i] == Diagonal::lambda(i) * y[i]);
    for (int j = 0; j < n; ++j) {
      const double expected = i == j ? Diagonal::lambda(i) * y[n + i * n + i] : 0.0;
      BOOST_TEST(dydt[n + i * n + j] == expected, "(" << i << ", " << j << ")");
    }
  }
}
