#pragma once

// Radau IIA of order 5 (3 stages, stage order 3, L-stable) with step-size control: the RADAU5
// algorithm of Hairer and Wanner for stiff systems. References:
//   [HW] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 2nd ed., Springer 1996:
//     Sect. IV.5 (Table 5.6, the tableau), Sect. IV.8 (the implementation: the simplified Newton
//     iteration in the transformed variables, its stopping criterion on the contraction rate
//     theta, starting values from the last collocation polynomial, the error estimate
//     err = (I - h gamma0 J)^{-1} (gamma0 h f(x0) + e1 Z1 + e2 Z2 + e3 Z3) and its second,
//     filtered form after a rejected or first step, and step size selection with Gustafsson's
//     predictive controller); the control constants and the transformation matrices T, T^{-1} are
//     those of Hairer's Fortran code radau5.f (version of 1996/2002).
//
// The tableau in closed form (c3 = 1, so x_{n+1} = x_n + Z3):
//   c1 = (4 - sqrt 6)/10, c2 = (4 + sqrt 6)/10,
//   A = [(88 - 7 sqrt 6)/360      (296 - 169 sqrt 6)/1800  (-2 + 3 sqrt 6)/225 ]
//       [(296 + 169 sqrt 6)/1800  (88 + 7 sqrt 6)/360      (-2 - 3 sqrt 6)/225 ]
//       [(16 - sqrt 6)/36         (16 + sqrt 6)/36         1/9                 ].
// A^{-1} has one real eigenvalue gamma = 30 / (6 + 81^{1/3} - 9^{1/3}) and a complex pair
// alpha -+ i beta with alpha + i beta = 1 / ((12 - 81^{1/3} + 9^{1/3})/60 + i (81^{1/3} + 9^{1/3})
// sqrt 3 / 60) (the roots of A's characteristic polynomial; radau5.f's U1, ALPH, BETA); T^{-1} A^{-1} T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]
// (checked in tests/runtime/stepper/radau5.cpp). With W = (T^{-1} (x) I) Z, each simplified Newton
// iteration solves one real n x n system with gamma/h I - J and one complex one with
// (alpha + i beta)/h I - J, each LU-factored once per (h, J) (Eigen PartialPivLU).
//
// What the step reuses: J is evaluated only when the last Newton iteration contracted slowly
// (theta > 0.001) or failed with a stale J; the LU factors only when h or J changed, and a proposed
// h within [1, 1.2] of the current one keeps the current one ([HW] Sect. IV.8, "Step size
// selection"; radau5.f's QUOT1, QUOT2). The Jacobian comes from sys.jacobian(t, x, J) where the
// system has one (HasJacobian), otherwise from forward differences (n extra system calls; radau5.f's
// increment sqrt(eps max(1e-5, |x_j|))); jacobian_source() says which.
//
// Tolerances: as in radau5.f, the user's (rtol, atol) become rtol' = 0.1 rtol^{2/3}, atol' = rtol'
// atol/rtol for the order-3 error estimate, so that the global error of the order-5 solution
// follows the requested tolerance; sc_i = atol' + rtol' |x_i| at the step's start.
//
// Dense output: the collocation polynomial through (t_n, x_n) and the three stages (degree 3), whose
// error is O(h^4) uniformly over the step (collocation: [HNW I] Sect. II.7), exact at the step ends.
//
// Failures: a Newton iteration that diverges, is too slow to converge within 7 iterations or meets
// a non-finite derivative rejects the attempt with a smaller step; when the steps then collapse, the
// driver's NoProgressChecker throws IntegrationError (step underflow, or non-finite derivative
// naming the component).

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"
#include "eomc/runtime/stepper/jacobian.hpp"

namespace eomc::runtime {

// The Radau IIA (s = 3) coefficients in scalar S: the tableau in closed form, the eigenvalues of
// A^{-1}, the transformation T and its inverse, and the error-estimate weights.
template <class S>
struct Radau5Tableau {
  S c1, c2;                 // c3 = 1
  S a[3][3];                // the Butcher matrix (for the tests; the step works in T's basis)
  S gamma, alpha, beta;     // eigenvalues of A^{-1}: gamma, alpha -+ i beta
  S T[3][3], TI[3][3];      // T^{-1} A^{-1} T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]
  S dd1, dd2, dd3;          // err = (gamma/h - J)^{-1} (f(x0) + (dd1 Z1 + dd2 Z2 + dd3 Z3)/h)

  static const Radau5Tableau& get() {
    static const Radau5Tableau t = make();
    return t;
  }

 private:
  static Radau5Tableau make() {
    using std::cbrt;
    using std::sqrt;
    Radau5Tableau t;
    const S s6 = sqrt(S(6)), c81 = cbrt(S(81)), c9 = cbrt(S(9));
    t.c1 = (S(4) - s6) / S(10);
    t.c2 = (S(4) + s6) / S(10);
    t.a[0][0] = (S(88) - S(7) * s6) / S(360);
    t.a[0][1] = (S(296) - S(169) * s6) / S(1800);
    t.a[0][2] = (S(-2) + S(3) * s6) / S(225);
    t.a[1][0] = (S(296) + S(169) * s6) / S(1800);
    t.a[1][1] = (S(88) + S(7) * s6) / S(360);
    t.a[1][2] = (S(-2) - S(3) * s6) / S(225);
    t.a[2][0] = (S(16) - s6) / S(36);
    t.a[2][1] = (S(16) + s6) / S(36);
    t.a[2][2] = S(1) / S(9);
    // The eigenvalues of A from the roots of its characteristic polynomial (radau5.f's U1, ALPH, BETA).
    t.gamma = S(30) / (S(6) + c81 - c9);
    const S ar = (S(12) - c81 + c9) / S(60), ai = (c81 + c9) * sqrt(S(3)) / S(60), norm = ar * ar + ai * ai;
    t.alpha = ar / norm;
    t.beta = ai / norm;
    // The error estimate's weights, gamma0 e_i in [HW]'s notation (radau5.f: DD1..DD3).
    t.dd1 = -(S(13) + S(7) * s6) / S(3);
    t.dd2 = (S(-13) + S(7) * s6) / S(3);
    t.dd3 = S(-1) / S(3);
    // radau5.f's T and T^{-1} (20 significant digits: long double accuracy).
    const long double T[3][3] = {{9.1232394870892942792e-02L, -0.14125529502095420843L, -3.0029194105147424492e-02L},
                                 {0.24171793270710701896L, 0.20412935229379993199L, 0.38294211275726193779L},
                                 {0.96604818261509293619L, 1.0L, 0.0L}};
    const long double TI[3][3] = {{4.3255798900631553510L, 0.33919925181580986954L, 0.54177053993587487119L},
                                  {-4.1787185915519047273L, -0.32768282076106238708L, 0.47662355450055045196L},
                                  {-0.50287263494578687595L, 2.5719269498556054292L, -0.59603920482822492497L}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        t.T[i][j] = S(T[i][j]);
        t.TI[i][j] = S(TI[i][j]);
      }
    return t;
  }
};

// radau5.f's control constants, with its defaults.
struct Radau5Settings {
  int max_newton = 7;            // NIT: Newton iterations per attempt
  double safety = 0.9;           // SAFE
  double fac_min = 0.2;          // the new step is at least fac_min times the old (radau5.f WORK(8))
  double fac_max = 8.0;          // and at most fac_max times (WORK(9))
  double jacobian_theta = 0.001; // THET: a new J only when the Newton contraction was slower
  double keep_h_low = 1.0;       // QUOT1, QUOT2: a proposal within [low, high] times h keeps h (and the LU)
  double keep_h_high = 1.2;
  bool predictive = true;        // Gustafsson's predictive controller ([HW] Sect. IV.8)
};

template <class S>
class Radau5 {
 public:
  using value_type = S;
  using Settings = Radau5Settings;
  using Tableau = Radau5Tableau<S>;
  static constexpr int order = 5;
  static constexpr int error_order = 3;  // the embedded estimate is O(h^4)
  static constexpr const char* name = "Radau5";
  enum class JacobianSource { none, symbolic, finite_difference };

  Radau5() = default;
  explicit Radau5(const Settings& settings) : opt_(settings) {}

  static const Tableau& tableau() { return Tableau::get(); }

  // f(t, x) for the step from (t, x); reused when (t, x) is where the last step ended. A state
  // or time moved behind the stepper's back drops the Jacobian, the LU and the starting values.
  template <class Sys>
    requires System<Sys, S>
  const State<S>& prepare(Sys& sys, const State<S>& x, S t) {
    if (!(f0_valid_ && t == t_f0_ && x == x_f0_)) {
      resize(x.size());
      sys(t, x, f0_);
      ++rhs_evals_;
      x_f0_ = x;
      t_f0_ = t;
      f0_valid_ = true;
      restart();
    }
    return f0_;
  }

  // One attempt from (t, x) with step h (either sign). Accepted: t and x advance, h becomes the
  // proposed next step, true. Rejected (error estimate above 1, or the Newton iteration failed):
  // t and x stay, h shrinks, false.
  template <class Sys>
    requires System<Sys, S>
  bool try_step(Sys& sys, State<S>& x, S& t, S& h, const Tolerances& tol) {
    using std::abs;
    using std::pow;
    using std::sqrt;
    if (h == S(0)) throw std::invalid_argument("Radau5::try_step: zero step size");
    prepare(sys, x, t);
    const Tableau& tab = tableau();
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    const S eps = std::numeric_limits<S>::epsilon();
    set_tolerances(tol);
    for (Eigen::Index i = 0; i < n; ++i) scal_[i] = atol_ + rtol_ * abs(x[std::size_t(i)]);

    if (need_jacobian_) {
      jacobian(sys, t, x);
      need_jacobian_ = false;
      jacobian_fresh_ = true;
      lu_valid_ = false;
    }
    if (!lu_valid_ || h != h_lu_) factor(h);
    const S fnewt = std::max(S(10) * eps / tol_ref_, std::min(S(0.03), sqrt(tol_ref_)));
    int newt = 0;
    if (const S shrink = newton(sys, x, t, h, fnewt, opt_.max_newton, newt); shrink > S(0))
      return newton_failed(h, shrink);

    // The error estimate [HW Sect. IV.8], filtered by (gamma/h - J)^{-1}; after a first or
    // rejected step a large estimate is filtered once more through f (stiff components).
    for (Eigen::Index i = 0; i < n; ++i) {
      e2_[i] = (tab.dd1 * z1_[i] + tab.dd2 * z2_[i] + tab.dd3 * z3_[i]) / h;
      err_[i] = f0_[std::size_t(i)] + e2_[i];
    }
    err_ = lu_real_.solve(err_);
    S err = scaled_norm(err_);
    if (err >= S(1) && (first_ || reject_)) {
      for (Eigen::Index i = 0; i < n; ++i) y_[std::size_t(i)] = x[std::size_t(i)] + err_[i];
      sys(t, static_cast<const State<S>&>(y_), f_);
      ++rhs_evals_;
      for (Eigen::Index i = 0; i < n; ++i) err_[i] = f_[std::size_t(i)] + e2_[i];
      err_ = lu_real_.solve(err_);
      err = scaled_norm(err_);
    }
    if (!(err == err)) return newton_failed(h, S(0.5));
    err = std::max(err, S(1e-10));
    last_error_ = err;

    // Step size selection ([HW] Sect. IV.8), the Newton iterations' count in the safety factor.
    const int nit = opt_.max_newton;
    const S cfac = S(opt_.safety) * S(1 + 2 * nit);
    const S fac = std::min(S(opt_.safety), cfac / S(newt + 2 * nit));
    const S facl = S(1) / S(opt_.fac_min), facr = S(1) / S(opt_.fac_max);
    S quot = std::max(facr, std::min(facl, pow(err, S(0.25)) / fac));
    S hnew = h / quot;

    if (err < S(1)) {
      // Gustafsson's predictive controller ([HW] Sect. IV.8, radau5.f's PRED).
      if (opt_.predictive) {
        if (accepted_ > 0) {
          S facgus = (h_acc_ / h) * pow(err * err / err_acc_, S(0.25)) / S(opt_.safety);
          facgus = std::max(facr, std::min(facl, facgus));
          quot = std::max(quot, facgus);
          hnew = h / quot;
        }
        h_acc_ = h;
        err_acc_ = std::max(S(1e-2), err);
      }
      ++accepted_;
      accept(sys, x, t, h);
      need_jacobian_ = theta_ > S(opt_.jacobian_theta);
      if (reject_ && abs(hnew) > abs(h)) hnew = h;
      reject_ = false;
      // A proposal barely above h keeps h, and with it the LU factors (unless J is renewed anyway).
      const S qt = hnew / h;
      if (!need_jacobian_ && qt >= S(opt_.keep_h_low) && qt <= S(opt_.keep_h_high)) hnew = h;
      h = hnew;
      return true;
    }
    // Rejected by the error estimate.
    reject_ = true;
    non_finite_component_ = IntegrationError::no_component;
    need_jacobian_ = !jacobian_fresh_;
    h = first_ ? h * S(0.1) : hnew;
    return false;
  }

  // A step of exactly h, no error control (fixed-step use, order tests): J at (t, x), the stage
  // equations solved to round-off (|dW| <= 1e3 eps relative to 1 + |x|). Throws IntegrationError
  // when the Newton iteration does not converge.
  template <class Sys>
    requires System<Sys, S>
  void do_step(Sys& sys, State<S>& x, S t, S h) {
    using std::abs;
    prepare(sys, x, t);
    const S eps = std::numeric_limits<S>::epsilon();
    for (std::size_t i = 0; i < x.size(); ++i) scal_[Eigen::Index(i)] = S(1) + abs(x[i]);
    jacobian(sys, t, x);
    factor(h);
    int newt = 0;
    if (newton(sys, x, t, h, S(1000) * eps, 50, newt) > S(0)) {
      if (non_finite_component_ != IntegrationError::no_component)
        throw IntegrationError::non_finite(t, "stage derivative", non_finite_component_);
      throw IntegrationError(IntegrationError::Kind::step_budget, static_cast<double>(t),
                             "Radau IIA stage equations did not converge at t = " + IntegrationError::format(t) +
                                 " with h = " + IntegrationError::format(h) + "; reduce the step");
    }
    accept(sys, x, t, h);
    need_jacobian_ = true;
  }

  // Dense output on the last accepted step: the collocation polynomial at tau.
  void calc_state(S tau, State<S>& out) const {
    if (!dense_valid_) throw std::logic_error("Radau5::calc_state: no accepted step to interpolate");
    const Tableau& tab = tableau();
    const S s = (tau - t_new_) / h_old_;  // in [-1, 0] on the step
    const S c1m1 = tab.c1 - S(1), c2m1 = tab.c2 - S(1);
    out.resize(x_new_.size());
    for (std::size_t i = 0; i < x_new_.size(); ++i) {
      const Eigen::Index k = static_cast<Eigen::Index>(i);
      out[i] = x_new_[i] + s * (cont1_[k] + (s - c2m1) * (cont2_[k] + (s - c1m1) * cont3_[k]));
    }
  }
  S previous_time() const { return t_old_; }
  S current_time() const { return t_new_; }
  bool has_dense_output() const { return dense_valid_; }

  // f(current_time(), x) after an accepted step, or f(t, x) after prepare().
  const State<S>& derivative() const { return f0_; }
  // After a Newton failure on a non-finite derivative: its first non-finite component.
  std::size_t last_non_finite_component() const { return non_finite_component_; }
  // The last attempt's error norm (<= 1: accepted).
  S last_error() const { return last_error_; }

  std::size_t rhs_evals() const { return rhs_evals_; }  // including finite-difference Jacobians
  std::size_t jacobian_evals() const { return jacobian_evals_; }
  std::size_t lu_decompositions() const { return lu_decompositions_; }  // pairs (real and complex)
  std::size_t newton_iterations() const { return newton_iterations_; }
  JacobianSource jacobian_source() const { return jacobian_source_; }

  // Compensated (Kahan) summation of x_{n+1} = x_n + Z3 (off by default); the carry is dropped
  // with the state's history (an edited state, reset()).
  void set_compensated(bool on) {
    compensated_ = on;
    std::fill(comp_.begin(), comp_.end(), S(0));
  }
  bool compensated() const { return compensated_; }

  // Forgets f(t, x), the Jacobian, the LU factors, the dense output and the controller's memory.
  void reset() {
    f0_valid_ = false;
    dense_valid_ = false;
    restart();
  }

 private:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using CVector = Eigen::Matrix<std::complex<S>, Eigen::Dynamic, 1>;
  using CMatrix = Eigen::Matrix<std::complex<S>, Eigen::Dynamic, Eigen::Dynamic>;

  // A new start at the prepared point: as radau5.f's first step.
  void restart() {
    first_ = true;
    reject_ = false;
    need_jacobian_ = true;
    jacobian_fresh_ = false;
    lu_valid_ = false;
    accepted_ = 0;
    faccon_ = S(1);
    std::fill(comp_.begin(), comp_.end(), S(0));
  }

  void resize(std::size_t n) {
    if (y_.size() == n) return;
    const Eigen::Index N = static_cast<Eigen::Index>(n);
    y_.assign(n, S(0));
    f_.assign(n, S(0));
    f0_.assign(n, S(0));
    comp_.assign(n, S(0));
    for (Vector* v : {&z1_, &z2_, &z3_, &w1_, &w2_, &w3_, &k1_, &k2_, &k3_, &r1_, &e2_, &err_, &scal_, &cont1_,
                      &cont2_, &cont3_})
      v->setZero(N);
    rc_.setZero(N);
    jac_.setZero(N, N);
    dense_valid_ = false;
  }

  void set_tolerances(const Tolerances& tol) {
    using std::pow;
    // radau5.f: rtol' = 0.1 rtol^{2/3}, atol' = rtol' (atol / rtol).
    if (tol.rtol > 0.0) {
      rtol_ = S(0.1) * pow(S(tol.rtol), S(2) / S(3));
      atol_ = rtol_ * (S(tol.atol) / S(tol.rtol));
      tol_ref_ = rtol_;
    } else {
      rtol_ = S(0);
      atol_ = S(0.1) * pow(S(tol.atol), S(2) / S(3));
      tol_ref_ = atol_;
    }
  }

  S scaled_norm(const Vector& e) const {
    using std::sqrt;
    S sum = S(0);
    for (Eigen::Index i = 0; i < e.size(); ++i) {
      const S r = ErrorChecker<S>::ratio(e[i], scal_[i]);
      sum += r * r;
    }
    return e.size() ? sqrt(sum / S(e.size())) : S(0);
  }

  // Starting values (the last step's collocation polynomial extrapolated, or zero) and the
  // simplified Newton iteration ([HW] Sect. IV.8) until faccon |dW| <= fnewt. Returns 0 when
  // converged (newt: the iterations used), else the factor for h: 1/2 on divergence, a non-finite
  // derivative or nit exhausted, radau5.f's prediction when the contraction is too slow.
  template <class Sys>
  S newton(Sys& sys, const State<S>& x, S t, S h, S fnewt, int nit, int& newt) {
    using std::pow;
    using std::sqrt;
    const Tableau& tab = tableau();
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    const S eps = std::numeric_limits<S>::epsilon();
    if (first_ || !dense_valid_ || t != t_new_) {
      z1_.setZero(n);
      z2_.setZero(n);
      z3_.setZero(n);
    } else {
      const S c3q = h / h_old_, c1q = tab.c1 * c3q, c2q = tab.c2 * c3q;
      const S c1m1 = tab.c1 - S(1), c2m1 = tab.c2 - S(1);
      for (Eigen::Index i = 0; i < n; ++i) {
        const S ak1 = cont1_[i], ak2 = cont2_[i], ak3 = cont3_[i];
        z1_[i] = c1q * (ak1 + (c1q - c2m1) * (ak2 + (c1q - c1m1) * ak3));
        z2_[i] = c2q * (ak1 + (c2q - c2m1) * (ak2 + (c2q - c1m1) * ak3));
        z3_[i] = c3q * (ak1 + (c3q - c2m1) * (ak2 + (c3q - c1m1) * ak3));
      }
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      w1_[i] = tab.TI[0][0] * z1_[i] + tab.TI[0][1] * z2_[i] + tab.TI[0][2] * z3_[i];
      w2_[i] = tab.TI[1][0] * z1_[i] + tab.TI[1][1] * z2_[i] + tab.TI[1][2] * z3_[i];
      w3_[i] = tab.TI[2][0] * z1_[i] + tab.TI[2][1] * z2_[i] + tab.TI[2][2] * z3_[i];
    }
    faccon_ = pow(std::max(faccon_, eps), S(0.8));
    theta_ = S(opt_.jacobian_theta);
    S dynold = S(0), thqold = S(0);
    newt = 0;
    const S fac1 = tab.gamma / h, alphn = tab.alpha / h, betan = tab.beta / h;
    for (;;) {
      if (newt >= nit) return S(0.5);
      if (!stage_derivatives(sys, x, t, h)) return S(0.5);
      // Right-hand sides in T's basis, then the real and the complex solve.
      for (Eigen::Index i = 0; i < n; ++i) {
        const S a1 = k1_[i], a2 = k2_[i], a3 = k3_[i];
        r1_[i] = tab.TI[0][0] * a1 + tab.TI[0][1] * a2 + tab.TI[0][2] * a3 - fac1 * w1_[i];
        const S s2 = tab.TI[1][0] * a1 + tab.TI[1][1] * a2 + tab.TI[1][2] * a3;
        const S s3 = tab.TI[2][0] * a1 + tab.TI[2][1] * a2 + tab.TI[2][2] * a3;
        rc_[i] = std::complex<S>(s2 - alphn * w2_[i] + betan * w3_[i], s3 - alphn * w3_[i] - betan * w2_[i]);
      }
      r1_ = lu_real_.solve(r1_);
      rc_ = lu_complex_.solve(rc_);
      ++newton_iterations_;
      ++newt;
      S dyno = S(0);
      for (Eigen::Index i = 0; i < n; ++i) {
        const S u = r1_[i] / scal_[i], v = rc_[i].real() / scal_[i], w = rc_[i].imag() / scal_[i];
        dyno += u * u + v * v + w * w;
      }
      dyno = sqrt(dyno / S(3 * n));
      if (!(dyno <= std::numeric_limits<S>::max())) return S(0.5);  // NaN or infinite: a singular E
      // Contraction rate theta and the predicted error after the remaining iterations ([HW] Sect. IV.8).
      if (newt > 1 && newt < nit) {
        const S thq = dyno / dynold;
        theta_ = newt == 2 ? thq : sqrt(thq * thqold);
        thqold = thq;
        if (!(theta_ < S(0.99))) return S(0.5);
        faccon_ = theta_ / (S(1) - theta_);
        const S dyth = faccon_ * dyno * pow(theta_, S(nit - 1 - newt)) / fnewt;
        if (dyth >= S(1)) {
          const S qnewt = std::max(S(1e-4), std::min(S(20), dyth));
          return S(0.8) * pow(qnewt, S(-1) / S(4 + nit - 1 - newt));
        }
      }
      dynold = std::max(dyno, eps);
      for (Eigen::Index i = 0; i < n; ++i) {
        w1_[i] += r1_[i];
        w2_[i] += rc_[i].real();
        w3_[i] += rc_[i].imag();
        z1_[i] = tab.T[0][0] * w1_[i] + tab.T[0][1] * w2_[i] + tab.T[0][2] * w3_[i];
        z2_[i] = tab.T[1][0] * w1_[i] + tab.T[1][1] * w2_[i] + tab.T[1][2] * w3_[i];
        z3_[i] = tab.T[2][0] * w1_[i] + tab.T[2][1] * w2_[i] + tab.T[2][2] * w3_[i];
      }
      if (faccon_ * dyno <= fnewt) return S(0);
    }
  }

  // The accepted step: x_{n+1} = x_n + Z3 (c3 = 1), the collocation polynomial's divided
  // differences for the dense output, and f(t + h, x_{n+1}) (FSAL for the driver and the next
  // error estimate).
  template <class Sys>
  void accept(Sys& sys, State<S>& x, S& t, S h) {
    const Tableau& tab = tableau();
    const S c1m1 = tab.c1 - S(1), c2m1 = tab.c2 - S(1), c1mc2 = tab.c1 - tab.c2;
    for (std::size_t k = 0; k < x.size(); ++k) {
      const Eigen::Index i = static_cast<Eigen::Index>(k);
      if (compensated_) {
        const S inc = z3_[i] - comp_[k];
        const S sum = x[k] + inc;
        comp_[k] = (sum - x[k]) - inc;
        x[k] = sum;
      } else {
        x[k] += z3_[i];
      }
      cont1_[i] = (z2_[i] - z3_[i]) / c2m1;
      const S ak = (z1_[i] - z2_[i]) / c1mc2;
      const S acont3 = (ak - z1_[i] / tab.c1) / tab.c2;
      cont2_[i] = (ak - cont1_[i]) / c1m1;
      cont3_[i] = cont2_[i] - acont3;
    }
    t_old_ = t;
    h_old_ = h;
    t = t + h;
    t_new_ = t;
    x_new_ = x;
    dense_valid_ = true;
    sys(t, static_cast<const State<S>&>(x), f0_);
    ++rhs_evals_;
    x_f0_ = x;
    t_f0_ = t;
    first_ = false;
    jacobian_fresh_ = false;
    non_finite_component_ = IntegrationError::no_component;
  }

  // The three stage derivatives at x + Z_i; false when one is not finite (its component noted).
  template <class Sys>
  bool stage_derivatives(Sys& sys, const State<S>& x, S t, S h) {
    using std::isfinite;
    const Tableau& tab = tableau();
    const S ct[3] = {t + tab.c1 * h, t + tab.c2 * h, t + h};
    const Vector* z[3] = {&z1_, &z2_, &z3_};
    Vector* k[3] = {&k1_, &k2_, &k3_};
    for (int s = 0; s < 3; ++s) {
      for (std::size_t i = 0; i < x.size(); ++i) y_[i] = x[i] + (*z[s])[Eigen::Index(i)];
      sys(ct[s], static_cast<const State<S>&>(y_), f_);
      ++rhs_evals_;
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (!isfinite(f_[i])) {
          non_finite_component_ = i;
          return false;
        }
        (*k[s])[Eigen::Index(i)] = f_[i];
      }
    }
    return true;
  }

  // A failed Newton iteration rejects the attempt with h scaled by `factor`; a stale J is renewed.
  bool newton_failed(S& h, S factor) {
    reject_ = true;
    need_jacobian_ = !jacobian_fresh_;
    last_error_ = std::numeric_limits<S>::infinity();
    h *= factor;
    return false;
  }

  template <class Sys>
  void jacobian(Sys& sys, S t, const State<S>& x) {
    using std::abs;
    using std::sqrt;
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    jac_.setZero(n, n);
    ++jacobian_evals_;
    if constexpr (HasJacobian<Sys, S>) {
      sys.jacobian(t, x, jac_);
      jacobian_source_ = JacobianSource::symbolic;
    } else {
      // Forward differences on f0 = f(t, x) (radau5.f's increment).
      const S eps = std::numeric_limits<S>::epsilon();
      y_ = x;
      for (Eigen::Index j = 0; j < n; ++j) {
        const std::size_t k = std::size_t(j);
        const S xj = x[k];
        const S delta = sqrt(eps * std::max(S(1e-5), abs(xj)));
        y_[k] = xj + delta;
        sys(t, static_cast<const State<S>&>(y_), f_);
        ++rhs_evals_;
        for (Eigen::Index i = 0; i < n; ++i) jac_(i, j) = (f_[std::size_t(i)] - f0_[std::size_t(i)]) / delta;
        y_[k] = xj;
      }
      jacobian_source_ = JacobianSource::finite_difference;
    }
  }

  // gamma/h I - J and (alpha + i beta)/h I - J, LU-factored.
  void factor(S h) {
    const Tableau& tab = tableau();
    Matrix e1 = -jac_;
    e1.diagonal().array() += tab.gamma / h;
    lu_real_.compute(e1);
    CMatrix e2 = (-jac_).template cast<std::complex<S>>();
    e2.diagonal().array() += std::complex<S>(tab.alpha / h, tab.beta / h);
    lu_complex_.compute(e2);
    ++lu_decompositions_;
    h_lu_ = h;
    lu_valid_ = true;
  }

  Settings opt_{};
  State<S> y_, f_, f0_, x_f0_, x_new_, comp_;
  Vector z1_, z2_, z3_, w1_, w2_, w3_, k1_, k2_, k3_, r1_, e2_, err_, scal_, cont1_, cont2_, cont3_;
  CVector rc_;
  Matrix jac_;
  Eigen::PartialPivLU<Matrix> lu_real_;
  Eigen::PartialPivLU<CMatrix> lu_complex_;
  S t_f0_ = S(0), t_old_ = S(0), t_new_ = S(0), h_old_ = S(1), h_lu_ = S(0), h_acc_ = S(0), err_acc_ = S(1);
  S rtol_ = S(0), atol_ = S(0), tol_ref_ = S(1), theta_ = S(0), faccon_ = S(1), last_error_ = S(0);
  bool f0_valid_ = false, first_ = true, reject_ = false, need_jacobian_ = true, jacobian_fresh_ = false;
  bool lu_valid_ = false, dense_valid_ = false, compensated_ = false;
  std::size_t accepted_ = 0;
  std::size_t rhs_evals_ = 0, jacobian_evals_ = 0, lu_decompositions_ = 0, newton_iterations_ = 0;
  std::size_t non_finite_component_ = IntegrationError::no_component;
  JacobianSource jacobian_source_ = JacobianSource::none;
};

static_assert(AdaptiveStepper<Radau5<double>> && DenseOutputStepper<Radau5<double>>);
static_assert(AdaptiveStepper<Radau5<long double>> && DenseOutputStepper<Radau5<long double>>);

}  // namespace eomc::runtime
