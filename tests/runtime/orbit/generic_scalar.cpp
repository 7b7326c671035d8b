// The Kepler runtime with a class-type scalar: a __float128 wrapper whose math functions are found
// by argument-dependent lookup, the shape the project's own quad type takes. Everything
// instantiates (the whole API), and, being 113-bit, it is an independent reference for the double
// solver and the double propagator (a different algorithm: the generic Halley / Newton iterations
// instead of the table expansion; the same universal-variable code at four times the precision).
// Built only where GCC's libquadmath is available (tests/runtime_kepler/CMakeLists.txt).
#define BOOST_TEST_MODULE runtime_kepler_generic_scalar
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "eomc/runtime/orbit/kepler.hpp"
#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "kepler_support.hpp"

namespace rt = eomc::runtime;
namespace kt = kepler_test;

using Q = kt::Quad;

namespace {
constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();
const Q eps_q = std::numeric_limits<Q>::epsilon();

std::array<Q, 6> widen(const std::array<double, 6>& x) {
  std::array<Q, 6> y;
  for (int i = 0; i < 6; ++i) y[i] = Q(x[i]);
  return y;
}
double size3(const std::array<double, 6>& x, int offset) {
  return std::sqrt(x[offset] * x[offset] + x[offset + 1] * x[offset + 1] + x[offset + 2] * x[offset + 2]);
}
}  // namespace

// The quad solver to its own precision: err = |f(E)|/(f'(E) ulp(E)) with f on the cancellation-free
// form in quad (the test's own series). Without a wider type the bound is that of the long-double
// case (kepler_equation.cpp): 4.5 ulps at worst; about 2 measured.
BOOST_AUTO_TEST_CASE(quad_elliptic_solver_to_its_precision) {
  double worst = 0;
  for (double e : {0.0, 0.1, 0.5, 0.9, 0.999999, 1 - 1e-12})
    for (int j = 1; j <= 60; ++j) {
      for (Q M : {Q(pi) * Q(j) / Q(60), Q(std::pow(10.0, -j / 4.0))}) {
        const Q E = rt::eccentric_from_mean(M, Q(e));
        const Q r = kt::elliptic_residual<Q>(E, M, Q(e));
        const Q d = kt::elliptic_derivative<Q>(E, Q(e));
        const Q u = nextafter(E, Q(10)) - E;
        worst = std::max(worst, static_cast<double>(abs(r) / (d * u)));
      }
    }
  BOOST_TEST_MESSAGE("quad elliptic: max err " << worst << " ulp (quad)");
  BOOST_TEST(worst <= 4.5);
  // Vallado Example 2-1 in quad: the printed 12 decimals of degrees.
  const Q E = rt::eccentric_from_mean(Q(235.4) * rt::kepler_detail::pi<Q>() / Q(180), Q(0.4));
  BOOST_TEST(static_cast<double>(abs(E * Q(180) / rt::kepler_detail::pi<Q>() - Q(220.512074767522))) <= 0.5e-12);
}

// The double solver against the quad root: |E - E_q| <= 0.55 ulp(E) (the bound derived in
// kepler_equation.cpp), now with a reference computed by a different method.
BOOST_AUTO_TEST_CASE(double_solver_against_the_quad_root) {
  double worst = 0;
  for (double e : {0.0, 0.05, 0.3, 0.6, 0.9, 0.99, 0.9999, 0.999999, 1 - 1e-9, 1 - 1e-12})
    for (int j = -200; j <= 200; ++j) {
      const double M = j == 0 ? 1e-300 : (j > 0 ? 1 : -1) * (std::abs(j) <= 100 ? pi * std::abs(j) / 100 : std::pow(10.0, -(std::abs(j) - 100) / 6.0));
      const double E = rt::eccentric_from_mean(M, e);
      const Q Eq = rt::eccentric_from_mean(Q(M), Q(e));
      const double err = static_cast<double>(abs(Q(E) - Eq)) / kt::ulp(E);
      worst = std::max(worst, err);
      BOOST_TEST(err <= 0.55, "e = " << e << ", M = " << M << ": " << err << " ulp");
    }
  BOOST_TEST_MESSAGE("double vs quad root: max " << worst << " ulp");
  // Hyperbolic likewise.
  for (double e : {1 + 1e-9, 1.1, 3.0})
    for (double M : {1e-8, 0.3, 5.0, 1e4}) {
      const double H = rt::hyperbolic_from_mean(M, e);
      const Q Hq = rt::hyperbolic_from_mean(Q(M), Q(e));
      BOOST_TEST(static_cast<double>(abs(Q(H) - Hq)) / kt::ulp(H) <= 0.55, "e = " << e << ", M = " << M);
    }
}

// The double propagator against the quad propagator from the same initial state, for ellipses,
// near-parabolic orbits (e = 1 -+ 1e-8, 1) and hyperbolas. Tolerance as in universal.cpp: a few
// ulps of the state plus a time error of a few ulps of |dt| worth |v| (or the acceleration) each.
BOOST_AUTO_TEST_CASE(double_propagator_against_quad) {
  const double mu = 1.0;
  for (double e : {0.2, 0.9, 1 - 1e-8, 1.0, 1 + 1e-8, 1.5, 6.0})
    for (double dt : {-300.0, -7.7, -0.01, 0.5, 3.0, 42.0, 1000.0}) {
      const double vp = std::sqrt(mu * (1 + e));
      const std::array<double, 6> x0{1, 0, 0, 0, vp * std::cos(1.1), vp * std::sin(1.1)};
      const std::array<double, 6> x = rt::propagate_kepler(x0, dt, mu);
      const std::array<Q, 6> xq = rt::propagate_kepler(widen(x0), Q(dt), Q(mu));
      const double r = std::max(size3(x, 0), 1.0), v = std::max(size3(x, 3), vp);
      const double span = e < 1 ? std::max(std::fabs(dt), 2 * pi * std::pow((1 - e) / (1 + e), -1.5)) : std::fabs(dt);
      for (int k = 0; k < 3; ++k) {
        BOOST_TEST(std::fabs(x[k] - static_cast<double>(xq[k])) <= 16 * eps * (r + v * span), "e = " << e << ", dt = " << dt);
        BOOST_TEST(std::fabs(x[k + 3] - static_cast<double>(xq[k + 3])) <= 16 * eps * (v + mu * span), "e = " << e << ", dt = " << dt);
      }
    }
}

// The rest of the API instantiates and behaves for the class type: conversions round-trip to a few
// hundred quad ulps relative (well-conditioned orbits, e = 0.3, i = 1), the universal solver
// satisfies the Lagrange identity, Stumpff functions have their exact values at 0.
BOOST_AUTO_TEST_CASE(whole_api_instantiates_for_a_class_scalar) {
  const Q mu(398600.4418);
  const rt::ClassicalElements<Q> el{Q(7000), Q(0.3), Q(1), Q(2), Q(0.5), Q(4)};
  const std::array<Q, 6> x = rt::cartesian_from_classical(el, mu);
  const rt::ClassicalElements<Q> b = rt::classical_from_cartesian(x, mu);
  const Q tol = Q(256) * eps_q;
  BOOST_TEST(static_cast<double>(abs(b.a - el.a) / el.a) <= static_cast<double>(tol));
  BOOST_TEST(static_cast<double>(abs(b.e - el.e)) <= static_cast<double>(tol));
  BOOST_TEST(static_cast<double>(abs(b.mean_anomaly - el.mean_anomaly)) <= static_cast<double>(tol * Q(4)));
  const std::array<Q, 6> y = rt::cartesian_from_equinoctial(rt::equinoctial_from_cartesian(x, mu), mu);
  const std::array<Q, 6> z = rt::cartesian_from_classical(rt::classical_from_delaunay(rt::delaunay_from_classical(el, mu), mu), mu);
  const std::array<Q, 6> w = rt::cartesian_from_classical(rt::classical_from_equinoctial(rt::equinoctial_from_classical(el)), mu);
  for (int k = 0; k < 6; ++k) {
    const Q scale = abs(x[k < 3 ? 0 : 3]) + abs(x[k < 3 ? 1 : 4]) + abs(x[k < 3 ? 2 : 5]);
    BOOST_TEST(static_cast<double>(abs(y[k] - x[k]) / scale) <= static_cast<double>(tol));
    BOOST_TEST(static_cast<double>(abs(z[k] - x[k]) / scale) <= static_cast<double>(tol));
    BOOST_TEST(static_cast<double>(abs(w[k] - x[k]) / scale) <= static_cast<double>(tol));
  }
  const Q nu = rt::true_from_mean(Q(1), Q(0.5));
  BOOST_TEST(static_cast<double>(abs(rt::mean_from_true(nu, Q(0.5)) - Q(1))) <= static_cast<double>(Q(16) * eps_q));
  const Q H = rt::hyperbolic_from_true(Q(1), Q(2));
  BOOST_TEST(static_cast<double>(abs(rt::true_from_hyperbolic(H, Q(2)) - Q(1))) <= static_cast<double>(Q(16) * eps_q));
  const rt::UniversalKepler<Q> k = rt::solve_universal_kepler(Q(100), Q(7000), Q(1000), Q(1) / Q(8000), mu);
  BOOST_TEST(static_cast<double>(abs(k.f * k.gdot - k.fdot * k.g - Q(1))) <= static_cast<double>(Q(64) * eps_q));
  BOOST_TEST((rt::stumpff(Q(0)).c2 == Q(1) / Q(2)));
  BOOST_TEST((rt::stumpff(Q(0)).c3 == Q(1) / Q(6)));
  try {
    rt::eccentric_from_mean(Q(1), Q(2));
    BOOST_ERROR("no KeplerError for e = 2");
  } catch (const rt::KeplerError& err) {
    BOOST_TEST((err.kind() == rt::KeplerError::Kind::invalid_input));
  }
}
