// rigid/euler_poinsot.hpp: the free rigid body in closed form. Known answers (mpmath, 30 digits),
// agreement with a converged numerical integration of Euler's equations and the quaternion
// kinematics, conservation of E, |K| and K in space to round-off for t up to 1e4, the symmetric,
// principal-axis and separatrix cases, and refused input.
#define BOOST_TEST_MODULE runtime_euler_poinsot
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include "eomc/runtime/rigid/euler_poinsot.hpp"

namespace rt = eomc::runtime;
using V3 = std::array<double, 3>;
using Q4 = std::array<double, 4>;

namespace {

const double eps = std::numeric_limits<double>::epsilon();

// Rotates v by the unit quaternion q (body -> space), in long double so that the measurement adds
// no rounding of double's size.
V3 rotate(const Q4& q, const V3& v) {
  using L = long double;
  const L w = q[0], x = q[1], y = q[2], z = q[3];
  const L r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                     {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                     {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  V3 out{};
  for (int i = 0; i < 3; ++i)
    out[static_cast<std::size_t>(i)] = static_cast<double>(r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2]);
  return out;
}

double norm3(const V3& v) { return std::hypot(v[0], v[1], v[2]); }

// Distance of two attitudes as quaternions, up to the sign (q and -q are one rotation).
double quaternion_distance(const Q4& a, const Q4& b) {
  double plus = 0, minus = 0;
  for (int i = 0; i < 4; ++i) {
    plus += (a[static_cast<std::size_t>(i)] + b[static_cast<std::size_t>(i)]) *
            (a[static_cast<std::size_t>(i)] + b[static_cast<std::size_t>(i)]);
    minus += (a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) *
             (a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]);
  }
  return std::sqrt(std::min(plus, minus));
}

// Classical RK4 in long double (64-bit significand) on y = (w1, w2, w3, e0, e1, e2, e3):
//   I1 w1' = (I2 - I3) w2 w3 (cyclic),  e' = 1/2 e (x) (0, w).
using Y = std::array<long double, 7>;
Y rhs(const V3& I, const Y& y) {
  Y d{};
  d[0] = (I[1] - I[2]) * y[1] * y[2] / I[0];
  d[1] = (I[2] - I[0]) * y[2] * y[0] / I[1];
  d[2] = (I[0] - I[1]) * y[0] * y[1] / I[2];
  const long double e0 = y[3], e1 = y[4], e2 = y[5], e3 = y[6], w1 = y[0], w2 = y[1], w3 = y[2];
  d[3] = 0.5L * (-e1 * w1 - e2 * w2 - e3 * w3);
  d[4] = 0.5L * (e0 * w1 + e2 * w3 - e3 * w2);
  d[5] = 0.5L * (e0 * w2 - e1 * w3 + e3 * w1);
  d[6] = 0.5L * (e0 * w3 + e1 * w2 - e2 * w1);
  return d;
}
Y rk4(const V3& I, Y y, long double T, long n) {
  const long double h = T / n;
  auto axpy = [](const Y& a, long double s, const Y& b) {
    Y r{};
    for (std::size_t i = 0; i < 7; ++i) r[i] = a[i] + s * b[i];
    return r;
  };
  for (long k = 0; k < n; ++k) {
    const Y k1 = rhs(I, y), k2 = rhs(I, axpy(y, h / 2, k1)), k3 = rhs(I, axpy(y, h / 2, k2)),
            k4 = rhs(I, axpy(y, h, k3));
    for (std::size_t i = 0; i < 7; ++i) y[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
  return y;
}

Q4 random_unit_quaternion(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Q4 q{g(rng), g(rng), g(rng), g(rng)};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

// M^2 - 2 E I2 with I2 the middle moment (which side of the separatrix).
double d2_of(const V3& I, const V3& w) {
  V3 s = I;
  std::sort(s.begin(), s.end());
  double d = 0;
  for (int i = 0; i < 3; ++i)
    d += I[static_cast<std::size_t>(i)] * (I[static_cast<std::size_t>(i)] - s[1]) *
         w[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(i)];
  return d;
}

struct Case {
  V3 I, w;
  Q4 q;
  double T;
};

// The closed form against RK4 at t = T, with the tolerance from RK4's own error.
//
// RK4's global error is C h^4 + O(h^5), so with runs of n and 2n steps the error of the finer run
// is (y_n - y_2n)/15 to leading order (Richardson), in the Euclidean norm of omega and of the
// quaternion. That estimate, doubled to cover the O(h^5) remainder (h is chosen so that the leading
// term dominates: the measured error/estimate is 0.93..1.04 on every case below, i.e. the closed
// form agrees with RK4 exactly as well as RK4 is accurate), is the tolerance, plus the closed
// form's own rounding:
// the phase tau = nu t + tau0 carries a relative error of a few eps, i.e. an absolute error of
// a few eps (1 + nu t), which moves omega by that times |omega'|/nu <= |omega| max(1, k)
// (|d sn/du| etc. <= 1) and the attitude by the same angle; 64 eps (1 + nu T) |y| bounds it with
// room. The long-double RK4 rounding (2n steps of 2^-64) is 1e-15 and negligible.
struct Comparison {
  double error, estimate;
};
Comparison compare_with_rk4(const Case& c, long n) {
  const auto body = rt::FreeRigidBody::from(c.I, c.w, c.q);
  Y y0{c.w[0], c.w[1], c.w[2], c.q[0], c.q[1], c.q[2], c.q[3]};
  const Y coarse = rk4(c.I, y0, c.T, n), fine = rk4(c.I, y0, c.T, 2 * n);
  const auto exact = body.at(c.T);
  // Euclidean norms throughout, so that estimate and error measure the same thing.
  double est_w = 0, est_q = 0, err_w = 0;
  Q4 qf{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double d = static_cast<double>(coarse[i] - fine[i]),
                 e = exact.omega[i] - static_cast<double>(fine[i]);
    est_w += d * d;
    err_w += e * e;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const double d = static_cast<double>(coarse[i + 3] - fine[i + 3]);
    est_q += d * d;
    qf[i] = static_cast<double>(fine[i + 3]);
  }
  est_w = std::sqrt(est_w) / 15;
  est_q = std::sqrt(est_q) / 15;
  err_w = std::sqrt(err_w);
  const double err_q = quaternion_distance(exact.quaternion, qf);
  const double w_scale = norm3(c.w);
  const double period = body.period();
  const double turns =
      std::isfinite(period) && period > 0 ? std::fabs(c.T) / period * 8 : std::fabs(c.T) * 10;
  const double round = 64 * eps * (1 + turns);
  const double tol_w = 2 * est_w + round * w_scale, tol_q = 2 * est_q + round;
  BOOST_TEST(err_w <= tol_w, "omega: error " << err_w << " > tolerance " << tol_w << " (I = " << c.I[0] << ","
                                             << c.I[1] << "," << c.I[2] << ")");
  BOOST_TEST(err_q <= tol_q, "attitude: error " << err_q << " > tolerance " << tol_q);
  BOOST_TEST_MESSAGE("  omega: error/estimate " << err_w / est_w << ", attitude: " << err_q / est_q);
  return {std::max(err_w / w_scale, err_q), std::max(est_w / w_scale, est_q)};
}

}  // namespace

// I = (2, 3, 5), w0 = (0.4, 0, 0.8) (M^2 > 2 E I2): the period 4K/nu and w(3) against mpmath's
// ellipk/ellipfun at 30 digits. The closed form evaluates K = R_F (Boost: within 2 eps), nu and
// the amplitudes a_i by a handful of roundings each, sn/cn/dn of tau = 3 nu within a few eps: the
// bound 16 eps relative (to |w| for the components) counts those with a factor of two of room.
BOOST_AUTO_TEST_CASE(known_period_and_omega) {
  const auto body = rt::FreeRigidBody::from({2, 3, 5}, {0.4, 0, 0.8}, {1, 0, 0, 0});
  const double period = 7.95501726895396013353359141929794;
  BOOST_TEST(std::fabs(body.period() - period) <= 16 * eps * period);
  const V3 w3{-0.284791417174063728152241447249, 0.280880488293488266984937716121,
              0.790076724286446955270333740083};
  const auto s = body.at(3);
  for (std::size_t i = 0; i < 3; ++i) BOOST_TEST(std::fabs(s.omega[i] - w3[i]) <= 16 * eps * norm3(w3));
  BOOST_TEST_MESSAGE("period error " << (body.period() - period) / period << ", w(3) errors "
                                     << s.omega[0] - w3[0] << " " << s.omega[1] - w3[1] << " "
                                     << s.omega[2] - w3[2]);
}

// Dzhanibekov's wing nut: I = (2, 3, 5), w0 = (0, 1, 0.01), near the separatrix (k^2 = 0.99950):
// w2 changes sign every 2K/nu = 23.1934916163577240171701414048695 (mpmath), half the period.
// The flip times are t = K/nu (2j + 1) (w1(0) = 0 puts tau0 = K: w2 = a2 sn(nu t + K) = a2 cd),
// where w2 = 0 to the rounding of a zero of sn at u = 2K j (absolute: a few eps of a2 per unit of
// u, with u <= 20 K here); w2 = -+a2 halfway.
BOOST_AUTO_TEST_CASE(dzhanibekov_flips) {
  const auto body = rt::FreeRigidBody::from({2, 3, 5}, {0, 1, 0.01}, {1, 0, 0, 0});
  const double half = 23.1934916163577240171701414048695;
  BOOST_TEST(std::fabs(body.period() / 2 - half) <= 16 * eps * half);
  for (int j = 0; j < 10; ++j) {
    const double flip = half / 2 + j * half;
    BOOST_TEST(std::fabs(body.at(flip).omega[1]) <= 64 * eps * (1 + j));
    const double between = body.at((j + 1) * half).omega[1];
    BOOST_TEST(between * (j % 2 == 0 ? -1 : 1) > 0.999);
    BOOST_TEST(body.at(flip - 1).omega[1] * body.at(flip + 1).omega[1] < 0);
  }
}

// sn, cn, dn from k'^2 (Bulirsch's Landen sequence) against Boost's jacobi_elliptic (which takes k)
// where k is well conditioned: both within a few eps, so 8 eps apart.
BOOST_AUTO_TEST_CASE(sncndn_matches_boost) {
  for (double k : {0.0, 0.1, 0.5, 0.9, 0.99}) {
    for (double u = -3; u <= 3; u += 0.0625) {
      double cn, dn;
      const double sn = boost::math::jacobi_elliptic(k, u, &cn, &dn);
      const auto s = rt::poinsot_detail::sncndn(u, (1 - k) * (1 + k));
      BOOST_TEST(std::fabs(s.sn - sn) <= 8 * eps);
      BOOST_TEST(std::fabs(s.cn - cn) <= 8 * eps);
      BOOST_TEST(std::fabs(s.dn - dn) <= 8 * eps);
    }
  }
}

// Random bodies (moments in [1, 10], any order) and initial states on both sides of the
// separatrix (one of each integrated backwards), symmetric bodies (about the largest and the smallest
// moment), and the near-separatrix wing nut, against RK4 over about 10 periods of omega.
BOOST_AUTO_TEST_CASE(agrees_with_numerical_integration) {
  std::mt19937_64 rng(20260510);
  std::uniform_real_distribution<double> moment(1, 10), comp(-1, 1);
  std::vector<Case> cases;
  int above = 0, below = 0;
  while (above < 4 || below < 4) {
    const V3 I{moment(rng), moment(rng), moment(rng)}, w{comp(rng), comp(rng), comp(rng)};
    const double d2 = d2_of(I, w);
    if (d2 > 0 && above < 4) {
      ++above;
    } else if (d2 < 0 && below < 4) {
      ++below;
    } else {
      continue;
    }
    cases.push_back({I, w, random_unit_quaternion(rng), 0});
  }
  cases.push_back({{2, 2, 5}, {0.3, -0.5, 0.7}, random_unit_quaternion(rng), 0});
  cases.push_back({{5, 3, 5}, {0.3, -0.5, 0.7}, random_unit_quaternion(rng), 0});
  cases.push_back({{2, 3, 5}, {0, 1, 0.01}, random_unit_quaternion(rng), 0});
  cases.push_back({{3, 5, 2}, {0.8, 0.4, -0.3}, random_unit_quaternion(rng), 0});
  double worst_ratio = 0;
  for (Case& c : cases) {
    const auto body = rt::FreeRigidBody::from(c.I, c.w, c.q);
    c.T = std::min(10 * body.period(), 120.0);
    if (&c == &cases[1] || &c == &cases[5]) c.T = -c.T;  // backwards in time, once on each side
    // 8000 and 16000 steps: h <= 0.015, RK4's error 1e-11..1e-9, far above the closed form's
    // rounding and small enough (nu h <= 0.05) that the h^4 term dominates.
    const long n = 8000;
    const Comparison r = compare_with_rk4(c, n);
    worst_ratio = std::max(worst_ratio, r.error / r.estimate);
    BOOST_TEST_MESSAGE("I = (" << c.I[0] << ", " << c.I[1] << ", " << c.I[2] << "), D2 = " << d2_of(c.I, c.w)
                               << ", T = " << c.T << ": error " << r.error << ", RK4 error estimate "
                               << r.estimate);
  }
  BOOST_TEST_MESSAGE("worst error/estimate " << worst_ratio);
}

// The separatrix exactly: I = (2, 3, 6), w0 = (3, 1/2, 1) has M^2 - 2 E I2 = 2 (-1) 9 + 6 (3) 1 = 0
// in exact arithmetic and in doubles. The body tends to rotation about axis 2; period() is infinite.
BOOST_AUTO_TEST_CASE(separatrix) {
  std::mt19937_64 rng(7);
  const Case c{{2, 3, 6}, {3, 0.5, 1}, random_unit_quaternion(rng), 4};
  const auto body = rt::FreeRigidBody::from(c.I, c.w, c.q);
  BOOST_TEST(std::isinf(body.period()));
  const Comparison r = compare_with_rk4(c, 1000);
  BOOST_TEST_MESSAGE("separatrix: error " << r.error << ", estimate " << r.estimate);
  // t -> inf: w -> (0, a2, 0) with a2^2 = w2^2 + I1 (I1 - I3)/(I2 (I2 - I3)) w1^2 = 1/4 + 8/9 9
  // (= 2 E/I2: all the energy about axis 2); sech(nu t) ~ 1e-140 at t = 200.
  const auto far = body.at(200);
  BOOST_TEST(std::fabs(far.omega[0]) < 1e-100);
  BOOST_TEST(std::fabs(far.omega[1] - std::sqrt(8.25)) <= 8 * eps * 3);
  // Continuity with the elliptic branch just off the separatrix (k'^2 ~ 1e-14): over t <= 1
  // the two differ by O(k'^2) times a modest factor.
  const auto near = rt::FreeRigidBody::from(c.I, {3, 0.5, 1 + 1e-14}, c.q);
  BOOST_TEST(std::isfinite(near.period()));
  for (double t : {0.25, 0.5, 1.0}) {
    const auto a = body.at(t), b = near.at(t);
    for (std::size_t i = 0; i < 3; ++i) BOOST_TEST(std::fabs(a.omega[i] - b.omega[i]) < 1e-11);
    BOOST_TEST(quaternion_distance(a.quaternion, b.quaternion) < 1e-11);
  }
}

// Rotation about a principal axis (also a sphere and omega = 0): omega stays, the attitude turns
// about omega at |omega|: e(t) = e0 (x) (cos(|w| t/2), sin(|w| t/2) w/|w|).
BOOST_AUTO_TEST_CASE(principal_axis_rotation) {
  std::mt19937_64 rng(11);
  const Q4 q0 = random_unit_quaternion(rng);
  const std::array<std::pair<V3, V3>, 5> cases{{{{2, 3, 5}, {0, 0.7, 0}},
                                                {{2, 3, 5}, {-1.5, 0, 0}},
                                                {{4, 4, 4}, {0.3, -0.2, 0.9}},
                                                {{2, 2, 5}, {0.3, -0.2, 0}},
                                                {{2, 3, 5}, {0, 0, 0}}}};
  for (const auto& [I, w] : cases) {
    const auto body = rt::FreeRigidBody::from(I, w, q0);
    BOOST_TEST(body.period() == 0.0);
    const double t = 7.5, rate = norm3(w);
    const Q4 r{std::cos(rate * t / 2), rate > 0 ? std::sin(rate * t / 2) * w[0] / rate : 0,
               rate > 0 ? std::sin(rate * t / 2) * w[1] / rate : 0,
               rate > 0 ? std::sin(rate * t / 2) * w[2] / rate : 0};
    const Q4 expect = rt::poinsot_detail::mul(q0, r);
    const auto s = body.at(t);
    BOOST_TEST(s.omega == w);
    BOOST_TEST(quaternion_distance(s.quaternion, expect) <= 8 * eps);
  }
}

// Permuting the body axes by a rotation (relabelling the principal axes) must not change the
// motion in space: the closed form for I = (2, 3, 5) and for I = (3, 5, 2) with the cyclically
// permuted omega and the attitude composed with the permutation agree to round-off.
BOOST_AUTO_TEST_CASE(axis_order_is_immaterial) {
  std::mt19937_64 rng(3);
  const Q4 q0 = random_unit_quaternion(rng);
  const V3 w{0.4, -0.3, 0.8};
  // Body axes relabelled (x, y, z) -> (y, z, x): v' = P v = (v_y, v_z, v_x), so R' = R P^T, and
  // P^T (e_x -> e_y -> e_z -> e_x) is the rotation by 2 pi/3 about (1, 1, 1): e' = e (x) pc with
  // pc = (cos pi/3, sin pi/3 (1, 1, 1)/sqrt 3) = (1, 1, 1, 1)/2.
  const Q4 pc{0.5, 0.5, 0.5, 0.5};
  const Q4 q1 = rt::poinsot_detail::mul(q0, pc);
  const auto a = rt::FreeRigidBody::from({2, 3, 5}, w, q0);
  const auto b = rt::FreeRigidBody::from({3, 5, 2}, {w[1], w[2], w[0]}, q1);
  for (double t : {0.3, 5.0, 40.0}) {
    const auto sa = a.at(t), sb = b.at(t);
    BOOST_TEST(std::fabs(sa.omega[1] - sb.omega[0]) <= 64 * eps * (1 + t));
    BOOST_TEST(std::fabs(sa.omega[2] - sb.omega[1]) <= 64 * eps * (1 + t));
    BOOST_TEST(std::fabs(sa.omega[0] - sb.omega[2]) <= 64 * eps * (1 + t));
    BOOST_TEST(quaternion_distance(rt::poinsot_detail::mul(sa.quaternion, pc), sb.quaternion) <=
               64 * eps * (1 + t));
  }
}

// omega is periodic with period(): after j periods it is back at omega0 up to the phase error
// of tau = nu t + tau0, a few eps (1 + nu t) (see compare_with_rk4), times |omega'|/nu <= |omega|:
// bound 16 eps (1 + nu t) |omega|, with nu t = 4 K j.
BOOST_AUTO_TEST_CASE(omega_is_periodic) {
  for (const auto& [I, w] : std::array<std::pair<V3, V3>, 3>{
           {{{2, 3, 5}, {0.4, 0, 0.8}}, {{2, 3, 5}, {0.9, 0.3, 0.1}}, {{6, 1, 4}, {0.2, 0.7, -0.3}}}}) {
    const auto body = rt::FreeRigidBody::from(I, w, {1, 0, 0, 0});
    const double T = body.period();
    for (int j : {1, 10, 1000}) {
      const auto s = body.at(j * T);
      const double nut = 4 * 3.5 * j;  // 4 K j with K < 3.5 for these moduli
      const double err = norm3({s.omega[0] - w[0], s.omega[1] - w[1], s.omega[2] - w[2]});
      BOOST_TEST(err <= 16 * eps * (1 + nut) * norm3(w), "j = " << j << ": " << err);
      BOOST_TEST_MESSAGE("periodic, j = " << j << ": " << err / (eps * norm3(w)) << " eps");
    }
  }
}

// E, |K| and K in space, R(t) I w(t), at times up to 1e4 on both sides of the separatrix, near it
// and for a symmetric body: to round-off, independent of t. Bound: w_i = s_i a_i (cn, sn, dn)
// with a_i from four roundings and a square root (<= 4 u, u = eps/2), sn and cn normalised to
// sn^2 + cn^2 = 1 within 3 u and dn from the Landen recursion (<= 2 u per level, <= 6 levels at
// these moduli: 12 u); E = 1/2 sum I_i w_i^2 then carries 2 (4 + 12) u + 3 u = 35 u, |K| half of
// that plus 3 u. For K in space the attitude adds its own: R_K, A(t) and Rz(phi) from a few atan2,
// sin, cos (a few u each) and four quaternion products (4 u each, relative to |K|): 64 u. The test
// bound is 64 eps = 128 u for all three.
BOOST_AUTO_TEST_CASE(conservation_to_round_off) {
  std::mt19937_64 rng(5);
  const std::array<std::pair<V3, V3>, 5> cases{{{{2, 3, 5}, {0.4, 0, 0.8}},
                                                {{2, 3, 5}, {0.9, 0.3, 0.1}},
                                                {{2, 3, 5}, {0, 1, 0.01}},
                                                {{3, 3, 1}, {0.2, 0.5, -0.7}},
                                                {{7.5, 1.25, 4}, {-0.6, 0.35, 0.45}}}};
  double worst = 0;
  for (const auto& [I, w] : cases) {
    const auto body = rt::FreeRigidBody::from(I, w, random_unit_quaternion(rng));
    const double E = body.energy(), M = body.angular_momentum_norm();
    const V3 K0 = body.angular_momentum();
    for (double t = 1e-3; t <= 1e4; t *= 1.7) {
      for (double sign : {1.0, -1.0}) {
        const auto s = body.at(sign * t);
        const V3 Kb{I[0] * s.omega[0], I[1] * s.omega[1], I[2] * s.omega[2]};
        const double Et = 0.5 * (Kb[0] * s.omega[0] + Kb[1] * s.omega[1] + Kb[2] * s.omega[2]);
        const V3 Ks = rotate(s.quaternion, Kb);
        const double eE = std::fabs(Et - E) / E, eM = std::fabs(norm3(Kb) - M) / M;
        const double eK = norm3({Ks[0] - K0[0], Ks[1] - K0[1], Ks[2] - K0[2]}) / M;
        worst = std::max({worst, eE / eps, eM / eps, eK / eps});
        BOOST_TEST(eE <= 64 * eps);
        BOOST_TEST(eM <= 64 * eps);
        BOOST_TEST(eK <= 64 * eps);
      }
    }
  }
  BOOST_TEST_MESSAGE("worst conservation error " << worst << " eps");
}

BOOST_AUTO_TEST_CASE(bad_input_throws) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const Q4 q{1, 0, 0, 0};
  for (const V3& I : {V3{0, 1, 1}, V3{1, -2, 1}, V3{1, 1, nan}, V3{inf, 1, 1}})
    BOOST_CHECK_THROW(rt::FreeRigidBody::from(I, {1, 0, 0}, q), std::invalid_argument);
  for (const V3& w : {V3{nan, 0, 0}, V3{0, inf, 0}})
    BOOST_CHECK_THROW(rt::FreeRigidBody::from({1, 2, 3}, w, q), std::invalid_argument);
  for (const Q4& bad : {Q4{1, 0, 0, 0.1}, Q4{0, 0, 0, 0}, Q4{nan, 0, 0, 0}, Q4{1, inf, 0, 0}})
    BOOST_CHECK_THROW(rt::FreeRigidBody::from({1, 2, 3}, {1, 0, 0}, bad), std::invalid_argument);
  BOOST_CHECK_NO_THROW(rt::FreeRigidBody::from({1, 2, 3}, {1, 0, 0}, {0.5, 0.5, 0.5, 0.5}));
}
