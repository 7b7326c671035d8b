// Orbital elements <-> Cartesian state (runtime/include/eomc/runtime/orbit/orbital_elements.hpp):
// round trips within a few ulps times the condition number, the singular cases and their
// conventional zeros, the modified equinoctial elements (regular at e = 0 and i = 0), the
// Delaunay variables, and bad input.
#define BOOST_TEST_MODULE runtime_kepler_elements
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "kepler_support.hpp"

namespace rt = eomc::runtime;
namespace kt = kepler_test;
using State = std::array<double, 6>;
using Classical = rt::ClassicalElements<double>;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();

std::array<double, 6> as_array(const Classical& el) { return {el.a, el.e, el.i, el.raan, el.argp, el.mean_anomaly}; }
double size3(const State& x, int offset) {
  return std::sqrt(x[offset] * x[offset] + x[offset + 1] * x[offset + 1] + x[offset + 2] * x[offset + 2]);
}
// Differences of elements; raan, argp and (on ellipses) the mean anomaly modulo 2 pi.
std::array<double, 6> element_diff(const Classical& a, const Classical& b) {
  const auto x = as_array(a), y = as_array(b);
  std::array<double, 6> d;
  for (int j = 0; j < 6; ++j) {
    d[j] = x[j] - y[j];
    if (j >= 3 && (j < 5 || a.e < 1)) d[j] = std::remainder(d[j], 2 * pi);
  }
  return d;
}

// Condition of each element with respect to a state error of relative size 1 in |r| (positions)
// and |v| (velocities), the form the state's rounding takes after a rotation:
// cond_j = sum_k |d el_j / d x_k| * (|r| or |v|), by central differences (step 1e-6 of the scale:
// the truncation error is ~1e-12 relative, the rounding error ~1e-10 relative, both far below the
// factor-of-two accuracy a condition number needs).
std::array<double, 6> condition(const State& x, double mu) {
  std::array<double, 6> cond{};
  const double r = size3(x, 0), v = size3(x, 3);
  for (int k = 0; k < 6; ++k) {
    const double scale = k < 3 ? r : v, h = 1e-6 * scale;
    State xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    const auto d = element_diff(rt::classical_from_cartesian(xp, mu), rt::classical_from_cartesian(xm, mu));
    for (int j = 0; j < 6; ++j) cond[j] += std::fabs(d[j] / (2 * h)) * scale;
  }
  return cond;
}

// The round-trip bound for element j: the forward conversion leaves the state within ~6 eps of
// |r| and |v| (perifocal formulas, then a rotation: two products and a sum per component), which
// the backward conversion turns into 6 eps cond_j, and the backward conversion rounds its own
// result (atan2, sqrt, a division: ~4 eps of the element, or of 1 for angles near 0). 16 eps cond_j
// + 4 eps (1 + |el_j|) covers both with room for the perturbation's direction being unfavourable.
void check_round_trip(const Classical& el, double mu, double& worst_ulps) {
  const State x = rt::cartesian_from_classical(el, mu);
  const Classical back = rt::classical_from_cartesian(x, mu);
  const auto d = element_diff(back, el);
  const auto cond = condition(x, mu);
  const auto v = as_array(el);
  static const char* names[6] = {"a", "e", "i", "raan", "argp", "M"};
  for (int j = 0; j < 6; ++j) {
    const double tol = 16 * eps * cond[j] + 4 * eps * (1 + std::fabs(v[j]));
    BOOST_TEST(std::fabs(d[j]) <= tol, names[j] << ": off by " << d[j] << " (tolerance " << tol << ") at a = " << el.a
                                                << ", e = " << el.e << ", i = " << el.i << ", raan = " << el.raan
                                                << ", argp = " << el.argp << ", M = " << el.mean_anomaly);
    worst_ulps = std::max(worst_ulps, std::fabs(d[j]) / kt::ulp(std::max(std::fabs(v[j]), 1.0)));
  }
}

}  // namespace

// Ellipses over e from 1e-6 to 0.95 and i from 0.01 to pi - 0.04, every orientation and anomaly
// quadrant. The message reports the largest error in ulps of max(|element|, 1) for the
// well-conditioned part (0.05 <= e <= 0.7, 0.5 <= i <= 2.5), where cond is O(1): a few tens.
BOOST_AUTO_TEST_CASE(classical_round_trip_ellipses) {
  double worst_all = 0, worst_good = 0;
  for (double mu : {1.0, 398600.4418})
    for (double a : {1.0, 7000.0})
      for (double e : {1e-6, 0.001, 0.05, 0.3, 0.7, 0.95})
        for (double i : {0.01, 0.5, 1.5, 2.5, 3.1})
          for (double raan : {0.3, 4.0})
            for (double argp : {1.0, 5.0})
              for (double M : {0.2, 3.0, 5.9}) {
                double w = 0;
                check_round_trip({a, e, i, raan, argp, M}, mu, w);
                worst_all = std::max(worst_all, w);
                if (e >= 0.05 && e <= 0.7 && i >= 0.5 && i <= 2.5) worst_good = std::max(worst_good, w);
              }
  BOOST_TEST_MESSAGE("classical round trip: " << worst_good << " ulp (well conditioned), " << worst_all << " ulp overall");
  BOOST_TEST(worst_good <= 64.0);  // the condition-based bound above, evaluated for cond ~ 1-3
}

BOOST_AUTO_TEST_CASE(classical_round_trip_hyperbolas) {
  double worst = 0;
  for (double e : {1.001, 1.2, 3.0, 30.0})
    for (double i : {0.2, 1.5, 2.9})
      for (double M : {-20.0, -2.0, 0.0, 0.5, 4.0})
        check_round_trip({-12000.0, e, i, 2.0, 0.7, M}, 398600.4418, worst);
  BOOST_TEST_MESSAGE("classical round trip, hyperbolas: " << worst << " ulp");
}

// State -> elements -> state: a well-conditioned composition for orbits away from e = 1 (the state
// comes back within a few ulps of |r| and |v|). Random states from a fixed seed, mu = 1, energies
// kept at least 0.05 from zero and e away from 1 (the bounds: 64 eps, as the element errors of
// cond * 16 eps map back through the inverse Jacobian and add the forward rounding).
BOOST_AUTO_TEST_CASE(state_round_trip_through_classical_and_equinoctial) {
  std::uint64_t seed = 88172645463325252ull;
  auto uniform = [&seed](double lo, double hi) {  // xorshift64: reproducible, no <random> state
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return lo + (hi - lo) * static_cast<double>(seed >> 11) * 0x1p-53;
  };
  int tested = 0;
  while (tested < 2000) {
    const State x{uniform(-2, 2), uniform(-2, 2), uniform(-2, 2), uniform(-1.2, 1.2), uniform(-1.2, 1.2), uniform(-1.2, 1.2)};
    const double r = size3(x, 0), v = size3(x, 3);
    if (r < 0.1 || std::fabs(v * v / 2 - 1 / r) < 0.05) continue;
    ++tested;
    const Classical el = rt::classical_from_cartesian(x, 1.0);
    if (std::fabs(el.e - 1) < 0.05) continue;
    const State y = rt::cartesian_from_classical(el, 1.0);
    const State z = rt::cartesian_from_equinoctial(rt::equinoctial_from_cartesian(x, 1.0), 1.0);
    for (int k = 0; k < 6; ++k) {
      const double scale = k < 3 ? r : v;
      BOOST_TEST(std::fabs(y[k] - x[k]) <= 64 * eps * scale, "classical, component " << k);
      BOOST_TEST(std::fabs(z[k] - x[k]) <= 64 * eps * scale, "equinoctial, component " << k);
    }
  }
}

// The singular cases of the classical elements, with states built exactly (z = vz = 0 makes
// h_x = h_y = 0 exactly; a circular speed leaves e at round-off):
//   equatorial prograde: i = 0, raan = 0, argp = longitude of periapsis atan2(e_y, e_x);
//   equatorial retrograde: i = pi, raan = 0, argp measured the other way, atan2(-e_y, e_x);
//   circular inclined: argp = 0, M = argument of latitude (angle from the node);
//   circular equatorial: raan = argp = 0, M = true longitude.
// Each also goes back to its state.
BOOST_AUTO_TEST_CASE(singular_cases_use_the_conventional_zeros) {
  const double mu = 1.0;
  auto back_to = [&](const Classical& el, const State& x) {
    const State y = rt::cartesian_from_classical(el, mu);
    for (int k = 0; k < 6; ++k) BOOST_TEST(std::fabs(y[k] - x[k]) <= 64 * eps * (k < 3 ? size3(x, 0) : size3(x, 3)));
  };
  // Circular equatorial at true longitude 2.2.
  {
    const double th = 2.2;
    const State x{std::cos(th), std::sin(th), 0, -std::sin(th), std::cos(th), 0};
    const Classical el = rt::classical_from_cartesian(x, mu);
    BOOST_TEST(el.i == 0.0);
    BOOST_TEST(el.raan == 0.0);
    BOOST_TEST(el.argp == 0.0);
    BOOST_TEST(el.e <= 16 * eps);
    BOOST_TEST(std::fabs(el.mean_anomaly - th) <= 8 * eps);
    back_to(el, x);
    // Retrograde: the same position moving the other way; M is the angle about -z.
    const State xr{x[0], x[1], 0, -x[3], -x[4], 0};
    const Classical er = rt::classical_from_cartesian(xr, mu);
    BOOST_TEST(er.i == pi);
    BOOST_TEST(er.raan == 0.0);
    BOOST_TEST(er.argp == 0.0);
    BOOST_TEST(std::fabs(er.mean_anomaly - (2 * pi - th)) <= 8 * eps);
    back_to(er, xr);
  }
  // Equatorial ellipse, periapsis at longitude 0.9, true anomaly 1.3 (mu = 1, p = 1.5, e = 0.4).
  {
    const double lp = 0.9, nu = 1.3, e = 0.4, p = 1.5;
    const double r = p / (1 + e * std::cos(nu)), vs = std::sqrt(mu / p);
    const double L = lp + nu;
    const State x{r * std::cos(L), r * std::sin(L), 0,
                  -vs * (std::sin(L) + e * std::sin(lp)), vs * (std::cos(L) + e * std::cos(lp)), 0};
    const Classical el = rt::classical_from_cartesian(x, mu);
    BOOST_TEST(el.i == 0.0);
    BOOST_TEST(el.raan == 0.0);
    BOOST_TEST(std::fabs(el.argp - lp) <= 16 * eps);
    BOOST_TEST(std::fabs(el.e - e) <= 16 * eps);
    BOOST_TEST(std::fabs(rt::true_from_mean(el.mean_anomaly, el.e) - nu) <= 32 * eps);
    back_to(el, x);
    // Retrograde: mirror in the xz plane (y -> -y) and reverse the motion sense with it.
    const State xr{x[0], -x[1], 0, x[3], -x[4], 0};
    const Classical er = rt::classical_from_cartesian(xr, mu);
    BOOST_TEST(er.i == pi);
    BOOST_TEST(er.raan == 0.0);
    BOOST_TEST(std::fabs(er.argp - lp) <= 16 * eps);  // periapsis at (cos lp, -sin lp): atan2(-e_y, e_x) = lp
    back_to(er, xr);
  }
  // Circular inclined: node on the x axis (raan = 0 by construction here: a tilt about x),
  // argument of latitude 0.7, inclination 0.6.
  {
    const double u = 0.7, inc = 0.6;
    const State x{std::cos(u), std::sin(u) * std::cos(inc), std::sin(u) * std::sin(inc),
                  -std::sin(u), std::cos(u) * std::cos(inc), std::cos(u) * std::sin(inc)};
    const Classical el = rt::classical_from_cartesian(x, mu);
    BOOST_TEST(el.e <= 16 * eps);
    BOOST_TEST(el.argp == 0.0);
    BOOST_TEST(std::fabs(el.i - inc) <= 8 * eps);
    BOOST_TEST(std::fabs(std::remainder(el.raan, 2 * pi)) <= 8 * eps);
    BOOST_TEST(std::fabs(el.mean_anomaly - u) <= 16 * eps);
    back_to(el, x);
  }
}

// Modified equinoctial elements [Walker-Ireland-Owens 1985] are regular where the classical ones
// are not: exactly circular and exactly equatorial orbits round-trip like any other, and the
// elements there are what the definitions give (f = g = 0 at e = 0, h = k = 0 at i = 0,
// L = true longitude, p = h^2/mu). They agree with the classical path: equinoctial <-> classical
// and both -> state give the same state.
BOOST_AUTO_TEST_CASE(equinoctial_elements_are_regular_at_e_0_and_i_0) {
  const double mu = 398600.4418;
  {
    const double R = 7000, vs = std::sqrt(mu / R), th = 5.5;
    const State x{R * std::cos(th), R * std::sin(th), 0, -vs * std::sin(th), vs * std::cos(th), 0};
    const rt::EquinoctialElements<double> q = rt::equinoctial_from_cartesian(x, mu);
    BOOST_TEST(std::fabs(q.p - R) <= 8 * eps * R);
    BOOST_TEST(std::fabs(q.f) <= 8 * eps);
    BOOST_TEST(std::fabs(q.g) <= 8 * eps);
    BOOST_TEST(q.h == 0.0);
    BOOST_TEST(q.k == 0.0);
    BOOST_TEST(std::fabs(q.L - th) <= 8 * eps * th);
    const State y = rt::cartesian_from_equinoctial(q, mu);
    for (int k = 0; k < 6; ++k) BOOST_TEST(std::fabs(y[k] - x[k]) <= 16 * eps * (k < 3 ? R : vs));
  }
  // Elements -> state -> elements for e = 0 and i = 0 exactly and for general orbits.
  for (double f : {0.0, 0.1, -0.6})
    for (double g : {0.0, 0.3})
      for (double h : {0.0, 0.2, -1.5})
        for (double k : {0.0, 0.4})
          for (double L : {0.0, 2.0, 6.0}) {
            const rt::EquinoctialElements<double> q{9000, f, g, h, k, L};
            const rt::EquinoctialElements<double> b = rt::equinoctial_from_cartesian(rt::cartesian_from_equinoctial(q, mu), mu);
            // p: relative (|h|^2 has a few roundings); f, g, h, k: absolute against 1 + |h|^2 + |k|^2
            // (the frame's normalisation s^2); L: absolute modulo 2 pi.
            const double s2 = 1 + h * h + k * k;
            BOOST_TEST(std::fabs(b.p - q.p) <= 16 * eps * q.p);
            BOOST_TEST(std::fabs(b.f - f) <= 16 * eps * s2);
            BOOST_TEST(std::fabs(b.g - g) <= 16 * eps * s2);
            BOOST_TEST(std::fabs(b.h - h) <= 16 * eps * s2);
            BOOST_TEST(std::fabs(b.k - k) <= 16 * eps * s2);
            BOOST_TEST(std::fabs(std::remainder(b.L - L, 2 * pi)) <= 16 * eps * s2 * (1 + L));
          }
  // The classical path and the equinoctial path to the state agree.
  for (double e : {0.0, 0.2, 0.9, 2.0})
    for (double i : {0.0, 0.4, 2.0})
      for (double M : {0.3, 2.5}) {
        const Classical el{e < 1 ? 8000.0 : -8000.0, e, i, 1.1, 2.3, M};
        const State x = rt::cartesian_from_classical(el, mu);
        const State y = rt::cartesian_from_equinoctial(rt::equinoctial_from_classical(el), mu);
        const double rv = size3(x, 0), vv = size3(x, 3);
        for (int k = 0; k < 6; ++k) BOOST_TEST(std::fabs(y[k] - x[k]) <= 32 * eps * (k < 3 ? rv : vv), "e = " << e << ", i = " << i);
        // And back to the classical elements (e = 0, i = 0: the conventional zeros move raan and
        // argp into M; compare the state they give instead).
        const State z = rt::cartesian_from_classical(rt::classical_from_equinoctial(rt::equinoctial_from_classical(el)), mu);
        for (int k = 0; k < 6; ++k) BOOST_TEST(std::fabs(z[k] - x[k]) <= 32 * eps * (k < 3 ? rv : vv), "e = " << e << ", i = " << i);
      }
}

// Delaunay variables (D. Brouwer, G.M. Clemence, Methods of Celestial Mechanics, Academic Press
// 1961): L = sqrt(mu a), G = L sqrt(1 - e^2), H = G cos i;
// the Kepler Hamiltonian -mu^2/(2 L^2) equals the orbit energy v^2/2 - mu/r of the state. Round
// trip: a and the angles come back to a few ulps; e = sqrt((L - G)(L + G))/L loses what the
// rounding of G (eps L) costs when L - G ~ L e^2/2 is small: relative error ~ eps/e^2; i likewise
// near 0 and pi: eps/sin^2 i.
BOOST_AUTO_TEST_CASE(delaunay_variables) {
  const double mu = 398600.4418;
  for (double e : {1e-4, 0.01, 0.3, 0.8})
    for (double i : {0.05, 1.0, 3.0}) {
      const Classical el{7000, e, i, 0.5, 1.5, 2.5};
      const rt::DelaunayElements<double> d = rt::delaunay_from_classical(el, mu);
      BOOST_TEST(d.l == el.mean_anomaly);
      BOOST_TEST(d.g == el.argp);
      BOOST_TEST(d.h == el.raan);
      BOOST_TEST(std::fabs(d.L - std::sqrt(mu * 7000)) <= 2 * eps * d.L);
      BOOST_TEST(std::fabs(d.H - d.G * std::cos(i)) <= 2 * eps * d.G);
      const State x = rt::cartesian_from_classical(el, mu);
      const double energy = size3(x, 3) * size3(x, 3) / 2 - mu / size3(x, 0);
      const double cond_energy = size3(x, 3) * size3(x, 3) / 2 + mu / size3(x, 0);
      BOOST_TEST(std::fabs(-mu * mu / (2 * d.L * d.L) - energy) <= 32 * eps * cond_energy);
      const Classical b = rt::classical_from_delaunay(d, mu);
      BOOST_TEST(std::fabs(b.a - el.a) <= 4 * eps * el.a);
      BOOST_TEST(std::fabs(b.e - e) <= 4 * eps * e * (1 + 1 / (e * e)));
      BOOST_TEST(std::fabs(b.i - i) <= 4 * eps * (1 + 1 / (std::sin(i) * std::sin(i))));
      BOOST_TEST(b.raan == el.raan);
      BOOST_TEST(b.argp == el.argp);
      BOOST_TEST(b.mean_anomaly == el.mean_anomaly);
    }
}

// The state names every formulation's CSV and summary use.
BOOST_AUTO_TEST_CASE(state_names) {
  const std::array<std::string, 6> cart{"x", "y", "z", "vx", "vy", "vz"}, cl{"a", "e", "i", "raan", "argp", "mean_anomaly"},
      eq{"p", "f", "g", "h", "k", "L"}, de{"l", "g", "h", "L", "G", "H"};
  for (int j = 0; j < 6; ++j) {
    BOOST_TEST(rt::cartesian_names[j] == cart[j]);
    BOOST_TEST(rt::classical_names[j] == cl[j]);
    BOOST_TEST(rt::equinoctial_names[j] == eq[j]);
    BOOST_TEST(rt::delaunay_names[j] == de[j]);
  }
}

namespace {
template <class F>
void expect_kepler_error(F&& f, const std::string& fragment) {
  try {
    f();
    BOOST_ERROR("no KeplerError thrown (expected one mentioning '" << fragment << "')");
  } catch (const rt::KeplerError& err) {
    BOOST_TEST((err.kind() == rt::KeplerError::Kind::invalid_input));
    BOOST_TEST(std::string(err.what()).find(fragment) != std::string::npos, err.what());
  }
}
}  // namespace

BOOST_AUTO_TEST_CASE(bad_input_throws_clear_errors) {
  const double mu = 1.0, nan = std::numeric_limits<double>::quiet_NaN();
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{1, 1.0, 0.1, 0, 0, 0}, mu); }, "parabolic orbit has no semi-major axis");
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{1, 1.5, 0.1, 0, 0, 0}, mu); }, "hyperbola needs a < 0");
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{-1, 0.5, 0.1, 0, 0, 0}, mu); }, "ellipse needs a > 0");
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{1, -0.1, 0.1, 0, 0, 0}, mu); }, "negative eccentricity");
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{1, 0.1, nan, 0, 0, 0}, mu); }, "element not finite");
  expect_kepler_error([&] { rt::cartesian_from_classical(Classical{1, 0.1, 0.1, 0, 0, 0}, -1.0); }, "mu not positive");
  expect_kepler_error([&] { rt::classical_from_cartesian(State{1, 0, 0, 2, 0, 0}, mu); }, "rectilinear");
  expect_kepler_error([&] { rt::classical_from_cartesian(State{2, 0, 0, 0, 1, 0}, mu); }, "parabolic orbit");
  expect_kepler_error([&] { rt::equinoctial_from_cartesian(State{1, 0, 0, 0, -1, 0}, mu); }, "retrograde equatorial");
  expect_kepler_error([&] { rt::equinoctial_from_classical(Classical{1, 0.1, pi, 0, 0, 0}); }, "retrograde equatorial");
  expect_kepler_error([&] { rt::cartesian_from_equinoctial(rt::EquinoctialElements<double>{-1, 0, 0, 0, 0, 0}, mu); },
                      "semi-latus rectum");
  expect_kepler_error([&] { rt::cartesian_from_equinoctial(rt::EquinoctialElements<double>{1, 2, 0, 0, 0, pi}, mu); },
                      "beyond the asymptote");
  expect_kepler_error([&] { rt::delaunay_from_classical(Classical{-1, 1.5, 0.1, 0, 0, 0}, mu); }, "need an ellipse");
  expect_kepler_error([&] { rt::classical_from_delaunay(rt::DelaunayElements<double>{0, 0, 0, 1, 2, 0}, mu); }, "0 < G <= L");
}
