#pragma once

// The free rigid body in closed form (the Euler-Poinsot case): body angular velocity omega(t) by
// Jacobi's elliptic functions and the attitude by an elliptic integral of the third kind, the
// rigid-body counterpart of orbit/kepler.hpp's two-body propagator.
//
//   Euler's equations   I1 w1' = (I2 - I3) w2 w3  (and cyclically),
//   kinematics          e' = 1/2 e (x) (0, w)   (e: unit quaternion body -> space, as quaternion.hpp)
//
// References:
//   [LL] L. D. Landau, E. M. Lifshitz, Mechanics, 3rd ed. (1976), Sect. 37: the solution
//     w1 = a1 cn tau, w2 = a2 sn tau, w3 = a3 dn tau (eqs. 37.10-37.12), its modulus and rate
//     (37.9), the case M^2 < 2 E I2 by exchanging axes 1 and 3, the separatrix (37.13), the
//     symmetric top (Sect. 33), and the precession rate of the Euler angle about M,
//     phi' = M (I1 w1^2 + I2 w2^2)/(I1^2 w1^2 + I2^2 w2^2) (37.15 and the problem after it).
//   [CFSZ] E. Celledoni, F. Fasso, N. Safstrom, A. Zanna, The exact computation of the free rigid
//     body motion and its use in splitting methods, SIAM J. Sci. Comput. 30 (2008) 2084-2112,
//     Sect. 2-3: R(t) = R_K Rz(phi(t)) A(t), with A(t) a rotation taking the body's momentum
//     direction to the pole, and phi(t) an elliptic integral of the third kind.
//   [DLMF] NIST Digital Library of Mathematical Functions, 19.25.5 and 19.25.14 (F and Pi in
//     Carlson's symmetric forms R_F, R_J), 22.6.1, 22.4.3 (sn, cn, dn identities and periods),
//     22.20 (the arithmetic-geometric mean), 19.2.8 (K = R_F(0, k'^2, 1)).
//   [Bulirsch] R. Bulirsch, Numerical calculation of elliptic integrals and elliptic functions,
//     Numer. Math. 7 (1965) 78-90: sn, cn, dn by the descending Landen (AGM) sequence, from the
//     complementary parameter k'^2 (the routine sncndn of Numerical Recipes, 2nd ed., Sect. 6.11).
//
// Why Carlson forms and k'^2: near the separatrix M^2 = 2 E I2 the modulus k -> 1 and a double k
// has lost the information in k'^2 = 1 - k^2 (k'^2 = 1e-20 rounds k to 1, and K(k) to infinity,
// while the body still flips every 2K/nu ~ 47/nu). Everything here is therefore computed from k'^2,
// formed as (I3 - I1)(M^2 - 2 E I2)/((I3 - I2)(M^2 - 2 E I1)) with M^2 - 2 E Ij = sum_i Ii (Ii - Ij)
// wi^2 (no cancellation but the one in M^2 - 2 E I2 itself, whose sign decides the case: that
// one is the problem's own conditioning). Boost.Math's ellint_1/ellint_3/jacobi_elliptic take k;
// its Carlson functions ellint_rf/ellint_rj take k'^2 directly, and with sn, cn, dn at hand F and
// Pi need no amplitude (no asin, no unwrapping by hand): Pi(n; am u, k) = sn R_F(cn^2, dn^2, 1) +
// (n/3) sn^3 R_J(cn^2, dn^2, 1, 1 - n sn^2) for |am u| <= pi/2 [DLMF 19.25.14], and whole half
// periods are counted with the complete integrals, am(u + 2K) = am(u) + pi [DLMF 22.16.2].
//
// Cases, after the body axes are permuted by a proper signed permutation (so that Euler's
// equations keep their form) into a working frame whose third axis is the one the polhode
// encircles:
//   principal    omega along a principal axis (any omega for a sphere, omega = 0 included):
//                omega constant, e(t) = e0 (x) exp(t (0, omega)/2);
//   M^2 > 2EI2   working axes I1 < I2 < I3, pole axis 3 (largest moment);
//   M^2 < 2EI2   working axes I1 > I2 > I3, pole axis 3 (smallest moment): [LL]'s "exchange 1 and
//                3"; every formula below is written so that it holds in both orders;
//   M^2 = 2EI2   (exactly, in the rounded data) the separatrix: sn -> tanh, cn, dn -> sech, k = 1,
//                and Pi in closed form; the body approaches rotation about axis 2 for t -> +-inf;
//   symmetric    I1 = I2 (the pole is the symmetry axis) is the case k = 0, n = 0 of the above:
//                sn = sin, cn = cos, dn = 1, Pi = F = u: regular precession [LL Sect. 33].
//
// Accuracy (measured by tests/runtime/rigid/euler_poinsot.cpp): the energy, |K| and the
// space-fixed K within 4.1 eps for any t up to 1e4 (bound asserted: 64 eps); omega(3) against
// mpmath within 1 eps; the phase of omega (and the angle phi) to eps times the elapsed nu t, the
// conditioning of the time itself (omega back at omega0 after 1000 periods: 2800 eps, 2.8 eps per
// period); against RK4 error/estimate 0.93..1.04 over ten periods, i.e. exact to the integrator's
// error. Double only.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>

namespace eomc::runtime {

namespace poinsot_detail {

using Quat = std::array<double, 4>;
using Vec = std::array<double, 3>;

// Hamilton product, scalar first (the convention of quaternion.hpp's e' = 1/2 e (x) w).
inline Quat mul(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
inline Quat conj(const Quat& a) { return {a[0], -a[1], -a[2], -a[3]}; }
inline Quat normalised(Quat a) {
  const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]);
  for (double& c : a) c /= n;
  return a;
}
// Rotation by angle about the coordinate axis `axis` (0, 1, 2).
inline Quat about_axis(int axis, double angle) {
  Quat q{std::cos(angle / 2), 0.0, 0.0, 0.0};
  q[static_cast<std::size_t>(axis + 1)] = std::sin(angle / 2);
  return q;
}

// The quaternion of a proper rotation matrix (Shepperd's method: the largest of the four
// squared components is taken from the diagonal, the others from off-diagonal sums; here only
// for the signed permutation matrices of the working frame, whose entries are exact).
inline Quat from_matrix(const std::array<Vec, 3>& m) {
  const double tr = m[0][0] + m[1][1] + m[2][2];
  Quat q{};
  if (tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2]) {
    q[0] = std::sqrt(1.0 + tr) / 2;
    q[1] = (m[2][1] - m[1][2]) / (4 * q[0]);
    q[2] = (m[0][2] - m[2][0]) / (4 * q[0]);
    q[3] = (m[1][0] - m[0][1]) / (4 * q[0]);
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    q[1] = std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) / 2;
    q[0] = (m[2][1] - m[1][2]) / (4 * q[1]);
    q[2] = (m[0][1] + m[1][0]) / (4 * q[1]);
    q[3] = (m[0][2] + m[2][0]) / (4 * q[1]);
  } else if (m[1][1] >= m[2][2]) {
    q[2] = std::sqrt(1.0 - m[0][0] + m[1][1] - m[2][2]) / 2;
    q[0] = (m[0][2] - m[2][0]) / (4 * q[2]);
    q[1] = (m[0][1] + m[1][0]) / (4 * q[2]);
    q[3] = (m[1][2] + m[2][1]) / (4 * q[2]);
  } else {
    q[3] = std::sqrt(1.0 - m[0][0] - m[1][1] + m[2][2]) / 2;
    q[0] = (m[1][0] - m[0][1]) / (4 * q[3]);
    q[1] = (m[0][2] + m[2][0]) / (4 * q[3]);
    q[2] = (m[1][2] + m[2][1]) / (4 * q[3]);
  }
  return q;
}

struct Sncndn {
  double sn, cn, dn;
};

// sn, cn, dn of (u | k^2 = 1 - kc2) for 0 <= kc2 <= 1 [Bulirsch; NR Sect. 6.11]: the descending
// Landen sequence a_{i+1} = (a_i + b_i)/2, b_{i+1} = sqrt(a_i b_i) from a_0 = 1, b_0 = k', the
// amplitude at the top, then back down. The AGM converges quadratically (the relative gap squares
// and shrinks 8x each step), so stopping at a gap of 1e-8 leaves ~1e-17 after the last mean:
// 5 steps for kc2 = 1e-2, 8 for 1e-16, 12 for 1e-300 and for the smallest subnormal (counted).
// kc2 = 0 is the separatrix limit tanh, sech, sech. Accurate for |u| up to about K; callers
// reduce u by whole periods first.
inline Sncndn sncndn(double u, double kc2) {
  if (kc2 == 0.0) {
    const double sech = 1.0 / std::cosh(u);
    return {std::tanh(u), sech, sech};
  }
  constexpr int max_steps = 13;
  std::array<double, max_steps + 1> em{}, en{};
  double a = 1.0, emc = kc2, c = 1.0;
  int l = 0;
  for (int i = 0; i < max_steps; ++i) {
    l = i;
    em[static_cast<std::size_t>(i)] = a;
    emc = std::sqrt(emc);
    en[static_cast<std::size_t>(i)] = emc;
    c = 0.5 * (a + emc);
    if (std::fabs(a - emc) <= 1e-8 * a) break;
    emc *= a;
    a = c;
  }
  u *= c;
  double sn = std::sin(u), cn = std::cos(u), dn = 1.0;
  if (sn != 0.0) {
    a = cn / sn;
    c *= a;
    for (int i = l; i >= 0; --i) {
      const double b = em[static_cast<std::size_t>(i)];
      a *= c;
      c *= dn;
      dn = (en[static_cast<std::size_t>(i)] + a) / (b + a);
      a = c / b;
    }
    a = 1.0 / std::sqrt(c * c + 1.0);
    sn = sn >= 0.0 ? a : -a;
    cn = c * sn;
  }
  return {sn, cn, dn};
}

inline bool finite(double x) { return std::isfinite(x); }

}  // namespace poinsot_detail

// The torque-free motion of a rigid body with principal moments `inertia` (body axes along the
// principal axes, any order, all positive; the triangle inequality of physical bodies is not
// required), from body angular velocity omega0 and attitude quaternion0 (unit, scalar first,
// body -> space) at t = 0. Everything but the time-dependent evaluation is done in from().
struct FreeRigidBody {
  struct State {
    std::array<double, 3> omega;       // body angular velocity
    std::array<double, 4> quaternion;  // body -> space, unit, scalar first
  };

  std::array<double, 3> inertia{};

  // Throws std::invalid_argument for a non-positive or non-finite moment, a non-finite omega0
  // component, a non-finite quaternion or one whose norm is off 1 by more than 1e-12 (a
  // normalised quaternion is within a few eps; it is renormalised here).
  static FreeRigidBody from(const std::array<double, 3>& inertia, const std::array<double, 3>& omega0,
                            const std::array<double, 4>& quaternion0) {
    namespace pd = poinsot_detail;
    for (int i = 0; i < 3; ++i) {
      const double v = inertia[static_cast<std::size_t>(i)];
      if (!pd::finite(v) || !(v > 0.0))
        throw std::invalid_argument("FreeRigidBody: principal moment I" + std::to_string(i + 1) +
                                    " not positive and finite: " + std::to_string(v));
    }
    for (int i = 0; i < 3; ++i)
      if (!pd::finite(omega0[static_cast<std::size_t>(i)]))
        throw std::invalid_argument("FreeRigidBody: angular velocity component " + std::to_string(i + 1) +
                                    " not finite");
    double qn2 = 0.0;
    for (double c : quaternion0) {
      if (!pd::finite(c)) throw std::invalid_argument("FreeRigidBody: quaternion component not finite");
      qn2 += c * c;
    }
    const double qn = std::sqrt(qn2);
    if (!(std::fabs(qn - 1.0) <= 1e-12))
      throw std::invalid_argument("FreeRigidBody: attitude quaternion not unit (|q| = " + std::to_string(qn) +
                                  ")");
    FreeRigidBody b;
    b.inertia = inertia;
    b.setup(omega0, pd::normalised(quaternion0));
    return b;
  }

  // The state at time t (either sign).
  State at(double t) const {
    namespace pd = poinsot_detail;
    if (kind_ == Kind::principal) {
      // e(t) = e0 (x) (cos(|w| t/2), sin(|w| t/2) w/|w|).
      const double h = rate_ * t / 2, s = std::sin(h);
      pd::Quat r{std::cos(h), 0.0, 0.0, 0.0};
      for (int i = 0; i < 3; ++i)
        r[static_cast<std::size_t>(i + 1)] =
            rate_ > 0.0 ? s * omega0_[static_cast<std::size_t>(i)] / rate_ : 0.0;
      return {omega0_, pd::normalised(pd::mul(q0_, r))};
    }
    const double tau = nu_ * t + tau0_;
    pd::Vec w{};  // working-frame omega
    double P;     // int_0^tau du/(1 - n sn^2 u)
    if (kind_ == Kind::separatrix) {
      // [LL 37.13]: sn -> tanh, cn = dn -> sech; int du/(1 + m tanh^2 u) = (u + sqrt(m) atan(sqrt(m)
      // tanh u))/(1 + m), m = -n >= 0 (partial fractions in tanh u).
      const double th = std::tanh(tau), sech = 1.0 / std::cosh(tau);
      w = {s_[0] * a_[0] * sech, s_[1] * a_[1] * th, s_[2] * a_[2] * sech};
      const double sm = std::sqrt(-n_);
      P = (tau + sm * std::atan(sm * th)) / (1.0 - n_);
    } else {
      const auto [periods, sn, cn, dn] = reduced(tau);
      const double sign = std::fmod(periods, 2.0) == 0.0 ? 1.0 : -1.0;  // sn, cn(u + 2K) = -sn, -cn
      w = {s_[0] * a_[0] * sign * cn, s_[1] * a_[1] * sign * sn, s_[2] * a_[2] * dn};
      P = 2.0 * periods * pi_complete_ + pi_incomplete(sn, cn, dn);
    }
    // phi' = M/I3 + M (I3 - I1)/(I1 I3) / (1 - n sn^2): [LL]'s rate with I1 w1^2 + I2 w2^2 = 2E - I3
    // w3^2 and I1^2 w1^2 + I2^2 w2^2 = I1^2 a1^2 (1 - n sn^2) (see setup()).
    const double phi = n_ == 0.0 ? precession_ * t : pole_rate_ * t + phi_scale_ * (P - P0_);
    State out;
    for (int i = 0; i < 3; ++i)
      out.omega[static_cast<std::size_t>(perm_[static_cast<std::size_t>(i)])] =
          sgn_[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(i)];
    const pd::Quat qa = pole_frame(w);
    out.quaternion = pd::normalised(pd::mul(pd::mul(qk_, pd::mul(pd::about_axis(2, phi), qa)), p_));
    return out;
  }

  // The period of omega(t), 4K/nu [LL 37.12]; +infinity on the separatrix; 0 when omega is constant.
  double period() const {
    if (kind_ == Kind::principal) return 0.0;
    if (kind_ == Kind::separatrix) return std::numeric_limits<double>::infinity();
    return 4.0 * K_ / nu_;
  }
  // The conserved quantities at t = 0: kinetic energy, |K|, K in space.
  double energy() const { return energy_; }
  double angular_momentum_norm() const { return M_; }
  std::array<double, 3> angular_momentum() const { return k_space_; }

 private:
  enum class Kind { principal, elliptic, separatrix };
  Kind kind_ = Kind::principal;
  std::array<int, 3> perm_{0, 1, 2};             // working axis i is body axis perm_[i] ...
  std::array<double, 3> sgn_{1.0, 1.0, 1.0};     // ... times sgn_[i] (a proper rotation)
  poinsot_detail::Quat p_{1.0, 0.0, 0.0, 0.0};   // that rotation: v_working = p v_body p*
  poinsot_detail::Quat qk_{1.0, 0.0, 0.0, 0.0};  // R_K: pole frame -> space at phi = 0
  poinsot_detail::Quat q0_{1.0, 0.0, 0.0, 0.0};
  std::array<double, 3> omega0_{}, I_{}, a_{}, s_{}, k_space_{};
  double rate_ = 0.0, energy_ = 0.0, M_ = 0.0;
  double nu_ = 0.0, tau0_ = 0.0, kc2_ = 0.0, n_ = 0.0, K_ = 0.0, pi_complete_ = 0.0, P0_ = 0.0;
  double pole_rate_ = 0.0, phi_scale_ = 0.0, precession_ = 0.0;

  struct Reduced {
    double periods, sn, cn, dn;  // tau = 2K periods + r, |r| <= K; sn, cn, dn of r
  };
  Reduced reduced(double tau) const {
    const double periods = std::nearbyint(tau / (2.0 * K_));
    const double r = tau - 2.0 * K_ * periods;
    const auto s = poinsot_detail::sncndn(r, kc2_);
    return {periods, s.sn, s.cn, s.dn};
  }
  // Pi(n; am r, k) for |am r| <= pi/2 from sn, cn, dn of r [DLMF 19.25.14].
  double pi_incomplete(double sn, double cn, double dn) const {
    if (sn == 0.0) return 0.0;
    const double c2 = cn * cn, d2 = dn * dn;
    double v = sn * boost::math::ellint_rf(c2, d2, 1.0);
    if (n_ != 0.0) v += n_ / 3.0 * sn * sn * sn * boost::math::ellint_rj(c2, d2, 1.0, 1.0 - n_ * sn * sn);
    return v;
  }
  // A(t) = Rx(theta) Rz(psi): [LL]'s Euler angles of the momentum in the working frame,
  // K/|K| = (sin theta sin psi, sin theta cos psi, cos theta); A maps that direction to e3.
  poinsot_detail::Quat pole_frame(const poinsot_detail::Vec& w) const {
    const double k1 = I_[0] * w[0], k2 = I_[1] * w[1], k3 = I_[2] * w[2];
    const double theta = std::atan2(std::hypot(k1, k2), k3), psi = std::atan2(k1, k2);
    return poinsot_detail::mul(poinsot_detail::about_axis(0, theta), poinsot_detail::about_axis(2, psi));
  }

  void setup(const std::array<double, 3>& omega0, const poinsot_detail::Quat& q0) {
    namespace pd = poinsot_detail;
    omega0_ = omega0;
    q0_ = q0;
    const auto& J = inertia;
    const auto& w0 = omega0;
    energy_ = 0.5 * (J[0] * w0[0] * w0[0] + J[1] * w0[1] * w0[1] + J[2] * w0[2] * w0[2]);
    M_ = std::hypot(J[0] * w0[0], J[1] * w0[1], J[2] * w0[2]);
    {
      const pd::Vec kb{J[0] * w0[0], J[1] * w0[1], J[2] * w0[2]};
      const pd::Quat ks = pd::mul(pd::mul(q0, {0.0, kb[0], kb[1], kb[2]}), pd::conj(q0));
      k_space_ = {ks[1], ks[2], ks[3]};
    }
    // omega along a principal axis: every pair of axes with different moments has a zero component.
    bool principal = true;
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        if (J[static_cast<std::size_t>(i)] != J[static_cast<std::size_t>(j)] &&
            w0[static_cast<std::size_t>(i)] != 0.0 && w0[static_cast<std::size_t>(j)] != 0.0)
          principal = false;
    if (principal) {
      kind_ = Kind::principal;
      rate_ = std::hypot(w0[0], w0[1], w0[2]);
      return;
    }

    // Ascending order; M^2 - 2 E I2 (middle moment) decides which extreme axis is the pole.
    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
      return J[static_cast<std::size_t>(x)] < J[static_cast<std::size_t>(y)];
    });
    auto D = [&](double Ij) {  // M^2 - 2 E Ij = sum_i Ii (Ii - Ij) wi^2, term by term
      double s = 0.0;
      for (int i = 0; i < 3; ++i)
        s += J[static_cast<std::size_t>(i)] * (J[static_cast<std::size_t>(i)] - Ij) *
             w0[static_cast<std::size_t>(i)] * w0[static_cast<std::size_t>(i)];
      return s;
    };
    const double D2 = D(J[static_cast<std::size_t>(order[1])]);
    if (D2 < 0.0) std::swap(order[0], order[2]);  // [LL]: exchange axes 1 and 3
    perm_ = order;
    // Parity of the permutation; the last axis takes its sign so that the map is a rotation.
    int inversions = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        if (order[static_cast<std::size_t>(i)] > order[static_cast<std::size_t>(j)]) ++inversions;
    sgn_ = {1.0, 1.0, inversions % 2 == 0 ? 1.0 : -1.0};
    std::array<pd::Vec, 3> P{};
    for (std::size_t i = 0; i < 3; ++i) P[i][static_cast<std::size_t>(order[i])] = sgn_[i];
    p_ = pd::normalised(pd::from_matrix(P));  // v_working = P v_body, so R_working = R P^T
    pd::Vec w{};
    for (std::size_t i = 0; i < 3; ++i) {
      I_[i] = J[static_cast<std::size_t>(order[i])];
      w[i] = sgn_[i] * w0[static_cast<std::size_t>(order[i])];
    }
    const double I1 = I_[0], I2 = I_[1], I3 = I_[2];
    // In either order (I1 < I2 < I3 with D2 > 0, or I1 > I2 > I3 with D2 < 0) the ratios below are
    // positive: I2 lies between I1 and I3 and Dj has the sign of I2 - Ij (Dj below).
    //   a1^2 = D3/(I1 (I1 - I3)), a2^2 = D3/(I2 (I2 - I3)), a3^2 = D1/(I3 (I3 - I1)),
    //   nu^2 = (I3 - I2) D1/(I1 I2 I3),  k^2 = (I2 - I1)(-D3)/((I3 - I2) D1),
    //   k'^2 = 1 - k^2 = (I3 - I1) D2/((I3 - I2) D1)  [(I3-I2) D1 + (I2-I1) D3 = (I3-I1) D2]
    // [LL 37.9-37.11], each written as w_i^2 plus a positive multiple of another w_j^2.
    const double a1 = std::sqrt(w[0] * w[0] + I2 * (I2 - I3) / (I1 * (I1 - I3)) * w[1] * w[1]);
    const double a2 = std::sqrt(w[1] * w[1] + I1 * (I1 - I3) / (I2 * (I2 - I3)) * w[0] * w[0]);
    const double a3 = std::sqrt(w[2] * w[2] + I2 * (I2 - I1) / (I3 * (I3 - I1)) * w[1] * w[1]);
    a_ = {a1, a2, a3};
    nu_ = std::sqrt((I3 - I2) * (I3 - I1) / (I1 * I2)) * a3;
    const double D1 = I2 * (I2 - I1) * w[1] * w[1] + I3 * (I3 - I1) * w[2] * w[2];
    // n of Pi: I1^2 w1^2 + I2^2 w2^2 = I1^2 a1^2 cn^2 + I2^2 a2^2 sn^2 = I1^2 a1^2 (1 - n sn^2),
    // n = 1 - I2^2 a2^2/(I1^2 a1^2) = I3 (I2 - I1)/(I1 (I2 - I3)) <= 0 in both orders (no pole of Pi).
    n_ = I3 * (I2 - I1) / (I1 * (I2 - I3));
    // phi' = M (2E - I3 w3^2)/(M^2 - I3^2 w3^2) = M/I3 + M (2 E I3 - M^2)/(I3 (M^2 - I3^2 w3^2))
    //      = M/I3 + M (I3 - I1)/(I1 I3) / (1 - n sn^2)   (2 E I3 - M^2 = -D3 = I1 (I3 - I1) a1^2).
    pole_rate_ = M_ / I3;
    const double rate_pi = M_ * (I3 - I1) / (I1 * I3);
    phi_scale_ = rate_pi / nu_;
    precession_ = M_ / I1;  // n = 0 (I1 = I2): phi' = M/I3 + M (I3 - I1)/(I1 I3) = M/I1, constant

    // Signs [LL's solution with general signs s_i, tau = nu t + tau0]: substituting
    // w = (s1 a1 cn, s2 a2 sn, s3 a3 dn) into Euler's equations gives s1 s2 s3 = sign(I3 - I2);
    // a shift of tau by 2K flips cn and sn, so s1 = +1 costs no generality. dn > 0 fixes s3 by w3
    // (w3 = 0 on a non-principal orbit only on the separatrix, where s1 is fixed by w1 instead).
    const double sigma = I3 > I2 ? 1.0 : -1.0;
    if (D2 == 0.0) {
      kind_ = Kind::separatrix;
      kc2_ = 0.0;
      // w1 and w3 keep their signs (sech > 0); tanh tau0 = w2/(s2 a2), sech tau0 = |w3|/a3.
      s_ = {w[0] > 0.0 ? 1.0 : -1.0, 0.0, w[2] > 0.0 ? 1.0 : -1.0};
      s_[1] = sigma * s_[0] * s_[2];
      tau0_ = std::asinh((w[1] / (s_[1] * a2)) / (std::fabs(w[2]) / a3));
      const double sm = std::sqrt(-n_);
      P0_ = (tau0_ + sm * std::atan(sm * std::tanh(tau0_))) / (1.0 - n_);
    } else {
      kind_ = Kind::elliptic;
      kc2_ = (I3 - I1) * D2 / ((I3 - I2) * D1);
      if (kc2_ > 1.0) kc2_ = 1.0;  // k^2 >= 0 (round-off only: I1 = I2 gives exactly 1)
      s_ = {1.0, sigma * (w[2] > 0.0 ? 1.0 : -1.0), w[2] > 0.0 ? 1.0 : -1.0};
      K_ = boost::math::ellint_rf(0.0, kc2_, 1.0);  // [DLMF 19.25.1]
      pi_complete_ = K_;
      if (n_ != 0.0) pi_complete_ += n_ / 3.0 * boost::math::ellint_rj(0.0, kc2_, 1.0, 1.0 - n_);
      // The initial amplitude phi0 (cos phi0 = cn tau0 = w1/a1, sin phi0 = sn tau0 = w2/(s2 a2)) and
      // tau0 = F(phi0): for |phi0| <= pi/2, F = sin R_F(cos^2, cos^2 + k'^2 sin^2, 1)
      // [DLMF 19.25.5]; beyond, F(phi0) = +-2K - F(+-pi - phi0) [DLMF 19.2.10].
      const double x = w[0] / a1, y = w[1] / (s_[1] * a2), r = std::hypot(x, y);
      const double s = y / r, c = std::fabs(x) / r;
      const double F = s * boost::math::ellint_rf(c * c, c * c + kc2_ * s * s, 1.0);
      tau0_ = x >= 0.0 ? F : (s >= 0.0 ? 2.0 * K_ : -2.0 * K_) - F;
      const auto red = reduced(tau0_);
      P0_ = 2.0 * red.periods * pi_complete_ + pi_incomplete(red.sn, red.cn, red.dn);
    }
    // R(0) = R_K Rz(0) A(0) P  =>  R_K = R(0) P^T A(0)^T.
    qk_ = pd::mul(pd::mul(q0, pd::conj(p_)), pd::conj(pole_frame(w)));
  }
};

}  // namespace eomc::runtime
