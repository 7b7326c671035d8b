// The universal-variable two-body propagator (kepler.hpp): Stumpff functions, Vallado's printed
// example, agreement with the elliptic and hyperbolic element paths, conservation of energy and
// angular momentum, a full period back to the start, near-parabolic orbits (continuity in the
// eccentricity and in time, Barker's equation at e = 1), and bad input.
#define BOOST_TEST_MODULE runtime_kepler_universal
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "eomc/runtime/orbit/kepler.hpp"
#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "kepler_support.hpp"

namespace rt = eomc::runtime;
namespace kt = kepler_test;
using W = long double;
using State = std::array<double, 6>;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();

double norm3(const State& x, int offset) {
  return std::sqrt(x[offset] * x[offset] + x[offset + 1] * x[offset + 1] + x[offset + 2] * x[offset + 2]);
}
double energy(const State& x, double mu) { return norm3(x, 3) * norm3(x, 3) / 2 - mu / norm3(x, 0); }
std::array<double, 3> angular_momentum(const State& x) {
  return {x[1] * x[5] - x[2] * x[4], x[2] * x[3] - x[0] * x[5], x[0] * x[4] - x[1] * x[3]};
}
double max_diff(const State& a, const State& b, int offset) {
  double d = 0;
  for (int i = offset; i < offset + 3; ++i) d = std::max(d, std::fabs(a[i] - b[i]));
  return d;
}

// Reference Stumpff functions in long double, written independently of the runtime: the half-angle
// closed forms for |z| >= 0.01 (x - sin x loses at most 9 of 64 bits there, leaving 2^-55) and the
// series to 30 terms below.
void stumpff_ref(W z, W& c2, W& c3) {
  if (std::fabs(z) >= 0.01L) {
    if (z > 0) {
      const W s = std::sqrt(z), h = std::sin(s / 2);
      c2 = 2 * h * h / z;
      c3 = (s - std::sin(s)) / (z * s);
    } else {
      const W s = std::sqrt(-z), h = std::sinh(s / 2);
      c2 = 2 * h * h / -z;
      c3 = (std::sinh(s) - s) / (-z * s);
    }
    return;
  }
  W t2 = 0.5L, t3 = 1.0L / 6;
  c2 = t2;
  c3 = t3;
  for (int k = 1; k < 30; ++k) {
    t2 *= -z / ((2 * k + 1) * (2 * k + 2));
    t3 *= -z / ((2 * k + 2) * (2 * k + 3));
    c2 += t2;
    c3 += t3;
  }
}

// Elements of an orbit with periapsis distance q, eccentricity e, and a fixed orientation.
rt::ClassicalElements<double> orbit(double a, double e, double M0) {
  return {a, e, 0.7, 1.3, 2.1, M0};
}

}  // namespace

// c2, c3 against the long-double reference, within 4 ulps (series: a dozen terms, first dominant;
// closed forms: the half-angle 1 - cos and x - sin x, each good to ~2 ulps) plus, beyond the series
// (|z| >= 2.5), the conditioning of sqrt(z): its rounding moves z by eps |z|, worth
// eps |z c'(z)| with c2' = (1 - z c3 - 2 c2)/(2z), c3' = (c2 - 3 c3)/(2z) (large near the zeros of
// c2 at sqrt z = 2 pi k and for z << 0, where cosh sqrt(-z) amplifies it by sqrt(-z)/2). Both sides
// of the switch at |z| = 2.5 are checked.
BOOST_AUTO_TEST_CASE(stumpff_functions) {
  std::vector<double> zs{0.0, 1e-300, -1e-300, 1e-12, -1e-12, 1e-4, -1e-4, 0.01, -0.01, 0.5, -0.5, 1, -1, 2.4999999999999996,
                         2.5, -2.4999999999999996, -2.5, 4, -4, 9.8, 39.4, 100, -100, 1e4, -400, -1e4 / 7};
  for (double z : zs) {
    const rt::Stumpff<double> c = rt::stumpff(z);
    W c2, c3;
    stumpff_ref(z, c2, c3);
    double cond2 = 0, cond3 = 0;
    if (std::fabs(z) >= 2.5) {
      cond2 = static_cast<double>(std::fabs((1 - z * c3 - 2 * c2) / 2));
      cond3 = static_cast<double>(std::fabs((c2 - 3 * c3) / 2));
    }
    BOOST_TEST(std::fabs(c.c2 - c2) <= 4 * eps * c2 + 2 * eps * cond2, "c2(" << z << ") = " << c.c2 << " vs " << static_cast<double>(c2));
    BOOST_TEST(std::fabs(c.c3 - c3) <= 4 * eps * c3 + 2 * eps * cond3, "c3(" << z << ") = " << c.c3 << " vs " << static_cast<double>(c3));
  }
  BOOST_TEST(rt::stumpff(0.0).c2 == 0.5);
  BOOST_TEST(rt::stumpff(0.0).c3 == 1.0 / 6);
}

// Vallado (4th ed.) Example 2-4: r0 = (1131.340, -2282.343, 6672.423) km, v0 = (-5.64305, 4.30333,
// 2.42879) km/s, mu = 398600.4418 km^3/s^2, 40 minutes later r = (-4219.7527, 4363.0292,
// -3958.7666) km, v = (3.689866, -1.916735, -6.112511) km/s; printed to 1e-4 km and 1e-6 km/s, so
// half a unit there is the tolerance (our double result differs from the long-double one by 1e-12).
BOOST_AUTO_TEST_CASE(vallado_example_2_4) {
  const State x0{1131.340, -2282.343, 6672.423, -5.64305, 4.30333, 2.42879};
  const State printed{-4219.7527, 4363.0292, -3958.7666, 3.689866, -1.916735, -6.112511};
  const State x = rt::propagate_kepler(x0, 2400.0, 398600.4418);
  for (int i = 0; i < 3; ++i) BOOST_TEST(std::fabs(x[i] - printed[i]) <= 0.5e-4, "r[" << i << "] = " << x[i]);
  for (int i = 3; i < 6; ++i) BOOST_TEST(std::fabs(x[i] - printed[i]) <= 0.5e-6, "v[" << i - 3 << "] = " << x[i]);
  // And back, within twice the one-way bound of the element-path test below (r_max ~ 7200 km,
  // v_max ~ 7.6 km/s over 2400 s).
  const State back = rt::propagate_kepler(x, -2400.0, 398600.4418);
  BOOST_TEST(max_diff(back, x0, 0) <= 2 * 16 * eps * (7200 + 7.6 * 2400));
}

// Ellipses: the universal propagator against the element path (state -> elements, M + n dt,
// Kepler, -> state) from the same initial state, over e from 0 to 0.99 and dt from a tenth of a
// period to 1000 periods, forwards and backwards. Both paths compute 1/a from the same state by
// the same formula, so they share its rounding (which at periapsis of e = 0.99 is amplified 200x
// by the cancellation in 2/r - v^2/mu) and agree on the mean motion. Tolerance: both paths round
// the state to a few ulps of its largest size (apoapsis a (1 + e) for positions, periapsis speed
// for velocities), and both carry a time error of a few ulps of max(|dt|, T) (M + n dt on one side,
// dt - k T on the other), worth v_max (or a_max = mu/q^2 for velocities) times that. 16 eps of
// each covers the dozen roundings on either side (the largest seen is a tenth of it).
BOOST_AUTO_TEST_CASE(universal_agrees_with_the_elliptic_element_path) {
  const double mu = 398600.4418, a = 7000;
  const double T = 2 * pi * std::sqrt(a * a * a / mu);
  for (double e : {0.0, 0.01, 0.3, 0.7, 0.9, 0.99})
    for (double M0 : {0.0, 0.4, 2.0, -2.9})
      for (double k : {0.1, -0.1, 0.37, 0.9, -0.9, 3.3, -12.7, 1000.37}) {
        const double dt = k * T;
        const State x0 = rt::cartesian_from_classical(orbit(a, e, M0), mu);
        const State x = rt::propagate_kepler(x0, dt, mu);
        rt::ClassicalElements<double> el = rt::classical_from_cartesian(x0, mu);
        el.mean_anomaly += std::sqrt(mu / (el.a * el.a * el.a)) * dt;
        const State ref = rt::cartesian_from_classical(el, mu);
        const double q = a * (1 - e), r_max = a * (1 + e), v_max = std::sqrt(mu * (1 + e) / q);
        const double span = std::max(std::fabs(dt), T);
        BOOST_TEST(max_diff(x, ref, 0) <= 16 * eps * (r_max + v_max * span), "e = " << e << ", M0 = " << M0 << ", dt/T = " << k);
        BOOST_TEST(max_diff(x, ref, 3) <= 16 * eps * (v_max + mu / (q * q) * span), "e = " << e << ", M0 = " << M0 << ", dt/T = " << k);
      }
}

// Hyperbolas: against the hyperbolic element path in the same way, e from 1.01 to 20, |dt| up to
// 1000 "periods" 2 pi/n (far along the asymptote). Tolerance as for ellipses, with r_max the
// largest distance of the two ends.
BOOST_AUTO_TEST_CASE(universal_agrees_with_the_hyperbolic_element_path) {
  const double mu = 398600.4418, a = -20000;
  const double n = std::sqrt(mu / -(a * a * a));
  for (double e : {1.01, 1.5, 3.0, 20.0})
    for (double M0 : {0.0, -3.0, 1.0})
      for (double k : {0.01, -0.3, 1.0, 7.5, -40.0, 1000.0}) {
        const double dt = k * 2 * pi / n;
        const State x0 = rt::cartesian_from_classical(orbit(a, e, M0), mu);
        const State x = rt::propagate_kepler(x0, dt, mu);
        rt::ClassicalElements<double> el = rt::classical_from_cartesian(x0, mu);
        el.mean_anomaly += std::sqrt(mu / -(el.a * el.a * el.a)) * dt;
        const State ref = rt::cartesian_from_classical(el, mu);
        const double q = a * (1 - e);
        const double r_max = std::max({norm3(x0, 0), norm3(ref, 0), q});
        const double v_max = std::sqrt(mu * (1 + e) / q);
        const double span = std::fabs(dt) + 2 * pi / n;
        BOOST_TEST(max_diff(x, ref, 0) <= 16 * eps * (r_max + v_max * span), "e = " << e << ", M0 = " << M0 << ", k = " << k);
        BOOST_TEST(max_diff(x, ref, 3) <= 16 * eps * (v_max + mu / (q * q) * span), "e = " << e << ", M0 = " << M0 << ", k = " << k);
      }
}

// Energy, angular momentum and the Lagrange identity f gdot - fdot g = 1 hold after any
// propagation. The f and g functions are not accumulated, so errors do not grow with dt along
// the orbit (a time error moves the state along the flow, which keeps energy and momentum):
// tolerances are 32 eps of the sizes involved (v^2/2 + mu/r at both ends; |r||v| at both ends).
// For the identity: f = 1 - U2/r0 and gdot = 1 - U2/r are differences with 1, so they carry
// absolute errors of eps (1 + |f|) and eps (1 + |gdot|), g and fdot relative ones; the identity
// then errs by at most ~2 eps (|f| + |gdot| + 2 |f gdot| + 2 |fdot g|). And r = F'(chi) from the
// solver agrees with |f r0 + g v0| to 32 eps of r plus the rounding of the terms f r0, g v0.
BOOST_AUTO_TEST_CASE(conservation_and_lagrange_identity) {
  const double mu = 1.0;
  std::vector<State> starts;
  for (double e : {0.0, 0.5, 0.97, 1 - 1e-8, 1.0, 1 + 1e-8, 1.5, 4.0}) {
    // Periapsis at r = 1 on the x axis, the orbit plane tilted about x.
    const double vp = std::sqrt(mu * (1 + e));
    starts.push_back({1, 0, 0, 0, vp * std::cos(0.4), vp * std::sin(0.4)});
  }
  starts.push_back({0.3, -1.1, 0.2, 0.5, 0.4, -0.6});  // an ellipse seen away from its apsides
  for (const State& x0 : starts)
    for (double dt : {1e-9, 0.3, -0.3, 2.0, 17.0, -55.5, 1000.0, -12345.6}) {
      const State x = rt::propagate_kepler(x0, dt, mu);
      const double scale_e = norm3(x0, 3) * norm3(x0, 3) / 2 + mu / norm3(x0, 0) + norm3(x, 3) * norm3(x, 3) / 2 + mu / norm3(x, 0);
      BOOST_TEST(std::fabs(energy(x, mu) - energy(x0, mu)) <= 32 * eps * scale_e, "dt = " << dt);
      const auto h0 = angular_momentum(x0), h = angular_momentum(x);
      const double scale_h = norm3(x0, 0) * norm3(x0, 3) + norm3(x, 0) * norm3(x, 3);
      for (int i = 0; i < 3; ++i) BOOST_TEST(std::fabs(h[i] - h0[i]) <= 32 * eps * scale_h, "dt = " << dt);
      // The same alpha as propagate_kepler (sum of squares, not |v|^2 via a square root).
      const double r0 = norm3(x0, 0), rv = x0[0] * x0[3] + x0[1] * x0[4] + x0[2] * x0[5];
      const double alpha = 2 / r0 - (x0[3] * x0[3] + x0[4] * x0[4] + x0[5] * x0[5]) / mu;
      const rt::UniversalKepler<double> k = rt::solve_universal_kepler(dt, r0, rv, alpha, mu);
      const double fg = std::fabs(k.f * k.gdot), fdg = std::fabs(k.fdot * k.g);
      BOOST_TEST(std::fabs(k.f * k.gdot - k.fdot * k.g - 1) <= 2 * eps * (std::fabs(k.f) + std::fabs(k.gdot) + 2 * fg + 2 * fdg),
                 "dt = " << dt);
      BOOST_TEST(std::fabs(k.r - norm3(x, 0)) <= 32 * eps * (k.r + std::fabs(k.f) * r0 + std::fabs(k.g) * norm3(x0, 3)), "dt = " << dt);
    }
}

// dt = 0 gives the initial state exactly; one period (reduced to dt = 0 internally) returns to it
// within the error of the period itself; seven steps of T/7 return to it within seven times the
// per-step bound of the element-path test (each step's error is carried, not amplified, by the
// following ones at this size: the along-track drift from an energy error of 32 eps is
// 3 pi * 32 eps * a per period, inside the same budget).
BOOST_AUTO_TEST_CASE(one_period_returns_to_the_start) {
  const double mu = 398600.4418, a = 26560;
  const double T = 2 * pi * std::sqrt(a * a * a / mu);
  for (double e : {0.0, 0.3, 0.7, 0.95}) {
    const State x0 = rt::cartesian_from_classical(orbit(a, e, 0.25), mu);
    BOOST_TEST((rt::propagate_kepler(x0, 0.0, mu) == x0));
    const double q = a * (1 - e), r_max = a * (1 + e), v_max = std::sqrt(mu * (1 + e) / q);
    const State once = rt::propagate_kepler(x0, T, mu);
    BOOST_TEST(max_diff(once, x0, 0) <= 16 * eps * (r_max + v_max * T), "e = " << e);
    State x = x0;
    for (int step = 0; step < 7; ++step) x = rt::propagate_kepler(x, T / 7, mu);
    BOOST_TEST(max_diff(x, x0, 0) <= 7 * 16 * eps * (r_max + v_max * T / 7), "e = " << e);
    BOOST_TEST(max_diff(x, x0, 3) <= 7 * 16 * eps * (v_max + mu / (q * q) * T / 7), "e = " << e);
  }
}

// Near-parabolic orbits, periapsis q = 1 (mu = 1), e = 1 - 1e-8, 1, 1 + 1e-8, over dt in
// [-60, 60]:
//  - at e = 1 the position matches Barker's equation D + D^3/3 = dt sqrt(mu/(2 q^3)),
//    r = q (1 + D^2), x = q (1 - D^2), y = 2 q D (Battin 4.2), within 16 eps (r + |v| |dt|);
//  - the three orbits differ by O(1e-8) (the state is smooth in e across e = 1): the difference,
//    divided by 1e-8, stays below 10 (1 + |dt|) (a bound on |dx/de| read off the parabola:
//    dx/de ~ dt v/2 + r), and is not zero;
//  - the state is continuous in time: x(t + h) matches x + h v + h^2/2 a(x) to h^3 |jerk|/3 with
//    h = 1e-3 (plus the round-off of both states), so no branch switch (series/closed form of the
//    Stumpff functions, conic type) jumps by more than ~1e-9.
BOOST_AUTO_TEST_CASE(near_parabolic_orbits_propagate_continuously) {
  const double mu = 1.0, q = 1.0;
  auto start = [&](double e) {
    return State{q, 0, 0, 0, std::sqrt(mu * (1 + e) / q), 0};
  };
  const State xm = start(1 - 1e-8), xp = start(1 + 1e-8), x1 = start(1.0);
  std::size_t steps = 0;
  for (double dt = -60; dt <= 60; dt += 0.37, ++steps) {
    const State ym = rt::propagate_kepler(xm, dt, mu), yp = rt::propagate_kepler(xp, dt, mu),
                y1 = rt::propagate_kepler(x1, dt, mu);
    // Barker at e = 1.
    // D = c - 1/c with c = (B + sqrt(B^2 + 1))^(1/3), B = 3/2 dt sqrt(mu/(2 q^3)); D is odd in B,
    // and forming c from |B| avoids the cancellation B + sqrt(B^2 + 1) for B << 0.
    const double B = 1.5 * dt * std::sqrt(mu / (2 * q * q * q));
    const double c = std::cbrt(std::fabs(B) + std::sqrt(B * B + 1));
    const double D = std::copysign(c - 1 / c, B);
    const double r = q * (1 + D * D);
    BOOST_TEST(std::fabs(y1[0] - q * (1 - D * D)) <= 16 * eps * (r + norm3(y1, 3) * std::fabs(dt)), "dt = " << dt);
    BOOST_TEST(std::fabs(y1[1] - 2 * q * D) <= 16 * eps * (r + norm3(y1, 3) * std::fabs(dt)), "dt = " << dt);
    BOOST_TEST(std::fabs(norm3(y1, 0) - r) <= 16 * eps * (r + norm3(y1, 3) * std::fabs(dt)), "dt = " << dt);
    // Smooth in e.
    const double spread = std::max(max_diff(ym, y1, 0), max_diff(yp, y1, 0)) / 1e-8;
    BOOST_TEST(spread <= 10 * (1 + std::fabs(dt)), "dt = " << dt << ": spread " << spread);
    if (dt != 0) BOOST_TEST(max_diff(ym, yp, 0) > 0);
    // Continuous in t.
    const std::array<std::pair<const State*, const State*>, 3> runs{{{&xm, &ym}, {&x1, &y1}, {&xp, &yp}}};
    for (const auto& [start_state, y] : runs) {
      const double h = 1e-3;
      const State z = rt::propagate_kepler(*start_state, dt + h, mu);
      const double rr = norm3(*y, 0), acc = mu / (rr * rr * rr);
      const double jerk = 4 * mu / (rr * rr * rr) * norm3(*y, 3);  // |d(-mu r/r^3)/dt| <= 4 mu |v|/r^3
      double worst = 0;
      for (int i = 0; i < 3; ++i)
        worst = std::max(worst, std::fabs(z[i] - ((*y)[i] + h * (*y)[i + 3] - h * h / 2 * acc * (*y)[i])));
      // Taylor remainder h^3/6 |jerk|, doubled for the jerk's variation over [t, t + h].
      BOOST_TEST(worst <= h * h * h * jerk / 3 + 64 * eps * (rr + norm3(*y, 3) * std::fabs(dt)), "dt = " << dt);
    }
  }
  BOOST_TEST(steps > 300u);
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
  constexpr double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const State x0{1, 0, 0, 0, 1, 0};
  expect_kepler_error([&] { rt::propagate_kepler(x0, 1.0, 0.0); }, "mu not positive");
  expect_kepler_error([&] { rt::propagate_kepler(x0, 1.0, -1.0); }, "mu not positive");
  expect_kepler_error([&] { rt::propagate_kepler(x0, nan, 1.0); }, "time of flight not finite");
  expect_kepler_error([&] { rt::propagate_kepler(x0, inf, 1.0); }, "time of flight not finite");
  expect_kepler_error([&] { rt::propagate_kepler(State{0, 0, 0, 0, 1, 0}, 1.0, 1.0); }, "|r0| not positive");
  expect_kepler_error([&] { rt::propagate_kepler(State{1, 0, 0, nan, 1, 0}, 1.0, 1.0); }, "not finite");
  expect_kepler_error([&] { rt::solve_universal_kepler(1.0, 1.0, 0.0, nan, 1.0); }, "alpha = 1/a not finite");
}
