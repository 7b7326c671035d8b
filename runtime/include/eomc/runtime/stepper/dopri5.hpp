#pragma once

// Dormand-Prince 5(4) with FSAL, embedded error estimate and Shampine's fourth-order continuous
// extension (dense output). References:
//   J.R. Dormand, P.J. Prince, "A family of embedded Runge-Kutta formulae", J. Comput. Appl. Math.
//     6 (1980) 19-26 (the tableau);
//   [HNW] Hairer-Norsett-Wanner I, Table 5.2 of Sect. II.5 (tableau), Sect. II.6 (dense output);
//   L.F. Shampine, "Some practical Runge-Kutta formulas", Math. Comp. 46 (1986) 135-150, through
//     the dense-output coefficients d_i of Hairer's code DOPRI5.
// Optionally with compensated (Kahan) summation of x_{n+1} = x_n + h sum b_i k_i (off by default;
// ControlledStepper::set_compensated).

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/control/controlled.hpp"
#include "eomc/runtime/control/step_adjuster.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"

namespace eomc::runtime {

// Coefficients as exact rationals evaluated in S, so long double gets long double accuracy.
template <class S>
struct DormandPrinceTableau {
  static constexpr S c2 = S(1) / S(5), c3 = S(3) / S(10), c4 = S(4) / S(5), c5 = S(8) / S(9);

  static constexpr S a21 = S(1) / S(5);
  static constexpr S a31 = S(3) / S(40), a32 = S(9) / S(40);
  static constexpr S a41 = S(44) / S(45), a42 = S(-56) / S(15), a43 = S(32) / S(9);
  static constexpr S a51 = S(19372) / S(6561), a52 = S(-25360) / S(2187), a53 = S(64448) / S(6561),
                     a54 = S(-212) / S(729);
  static constexpr S a61 = S(9017) / S(3168), a62 = S(-355) / S(33), a63 = S(46732) / S(5247),
                     a64 = S(49) / S(176), a65 = S(-5103) / S(18656);
  // Fifth-order weights b_i (= a7i, hence FSAL: stage 7 is f at the new point; b2 = b7 = 0).
  static constexpr S b1 = S(35) / S(384), b3 = S(500) / S(1113), b4 = S(125) / S(192),
                     b5 = S(-2187) / S(6784), b6 = S(11) / S(84);
  // e_i = b_i - bhat_i, bhat the fourth-order embedded weights (bhat7 = 1/40).
  static constexpr S e1 = S(71) / S(57600), e3 = S(-71) / S(16695), e4 = S(71) / S(1920),
                     e5 = S(-17253) / S(339200), e6 = S(22) / S(525), e7 = S(-1) / S(40);
  // Dense output (Shampine 1986, as in DOPRI5).
  static constexpr S d1 = S(-12715105075LL) / S(11282082432LL), d3 = S(87487479700LL) / S(32700410799LL),
                     d4 = S(-10690763975LL) / S(1880347072LL), d5 = S(701980252875LL) / S(199316789632LL),
                     d6 = S(-1453857185LL) / S(822651844LL), d7 = S(69997945LL) / S(29380423LL);
};

// The Dormand-Prince 5(4) pair as an error stepper (stepper/concepts.hpp): the stages, the
// error estimate, the dense output; ControlledStepper (control/controlled.hpp) adds the control.
template <class S>
class Dopri5ErrorStepper {
 public:
  using value_type = S;
  static constexpr int order = 5, error_order = 4;
  static constexpr const char* name = "Dopri5";

  template <class Sys>
  void evaluate_first(Sys& sys, S t, const State<S>& x) {
    resize(x.size());
    sys(t, x, k1_);
    ++rhs_evals_;
  }
  const State<S>& first_derivative() const { return k1_; }

  // Stages 2..7 and the error norm ||h sum e_i k_i|| ([HNW] (4.10)-(4.11), ErrorChecker).
  template <class Sys, class Checker>
  S attempt(Sys& sys, const State<S>& x, S t, S h, const Checker& checker, const S* comp, S* comp_new) {
    stages(sys, x, t, h, comp, comp_new);
    using T = DormandPrinceTableau<S>;
    for (std::size_t i = 0; i < x.size(); ++i)
      err_[i] = h * (T::e1 * k1_[i] + T::e3 * k3_[i] + T::e4 * k4_[i] + T::e5 * k5_[i] + T::e6 * k6_[i] +
                     T::e7 * k7_[i]);
    return checker.norm(err_, x, y_);
  }

  template <class Sys>
  void advance(Sys& sys, const State<S>& x, S t, S h, const S* comp, S* comp_new) {
    stages(sys, x, t, h, comp, comp_new);
  }

  // Commits the step (t, x) -> (t+h, y_): dense-output coefficients, x, FSAL derivative.
  template <class Sys>
  void accept(Sys&, State<S>& x, S t, S h) {
    using T = DormandPrinceTableau<S>;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const S dx = y_[i] - x[i];
      r1_[i] = x[i];
      r2_[i] = dx;
      r3_[i] = h * k1_[i] - dx;
      r4_[i] = dx - h * k7_[i] - r3_[i];
      r5_[i] = h * (T::d1 * k1_[i] + T::d3 * k3_[i] + T::d4 * k4_[i] + T::d5 * k5_[i] + T::d6 * k6_[i] +
                    T::d7 * k7_[i]);
      x[i] = y_[i];  // copy, not swap: the caller's buffer (and pointers into it) stay put
    }
    t_old_ = t;
    h_old_ = h;
    t_new_ = t + h;
    dense_valid_ = true;
    k1_.swap(k7_);
  }

  // Dense output on the last accepted step [t_old, t_new] ([HNW] Sect. II.6, DOPRI5's CONTD5):
  //   u(theta) = r1 + theta*(r2 + (1-theta)*(r3 + theta*(r4 + (1-theta)*r5))),  theta = (tau-t_old)/h,
  // a fourth-order interpolant (local error O(h^5)) that is C1 across steps. Values of tau outside
  // the step extrapolate the polynomial.
  void calc_state(S tau, State<S>& out) const {
    if (!dense_valid_) throw std::logic_error("Dopri5::calc_state: no accepted step yet");
    const S theta = (tau - t_old_) / h_old_, theta1 = S(1) - theta;
    out.resize(r1_.size());
    for (std::size_t i = 0; i < r1_.size(); ++i)
      out[i] = r1_[i] + theta * (r2_[i] + theta1 * (r3_[i] + theta * (r4_[i] + theta1 * r5_[i])));
  }

  S previous_time() const { return t_old_; }
  S current_time() const { return t_new_; }
  bool has_dense_output() const { return dense_valid_; }
  void invalidate_dense_output() { dense_valid_ = false; }
  std::size_t rhs_evals() const { return rhs_evals_; }

  std::size_t locate_non_finite() const {
    for (const State<S>* k : {&k2_, &k3_, &k4_, &k5_, &k6_, &y_, &k7_}) {
      const std::size_t i = first_non_finite(*k);
      if (i != IntegrationError::no_component) return i;
    }
    return first_non_finite(err_);
  }

 private:
  // Stages 2..7 from (t, x) with step h; leaves the fifth-order solution in y_ and f(t+h, y_) in k7_.
  template <class Sys>
  void stages(Sys& sys, const State<S>& x, S t, S h, const S* comp, S* comp_new) {
    using T = DormandPrinceTableau<S>;
    const std::size_t n = x.size();
    const State<S>& y = y_;
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i] + h * T::a21 * k1_[i];
    sys(t + T::c2 * h, y, k2_);
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i] + h * (T::a31 * k1_[i] + T::a32 * k2_[i]);
    sys(t + T::c3 * h, y, k3_);
    for (std::size_t i = 0; i < n; ++i)
      y_[i] = x[i] + h * (T::a41 * k1_[i] + T::a42 * k2_[i] + T::a43 * k3_[i]);
    sys(t + T::c4 * h, y, k4_);
    for (std::size_t i = 0; i < n; ++i)
      y_[i] = x[i] + h * (T::a51 * k1_[i] + T::a52 * k2_[i] + T::a53 * k3_[i] + T::a54 * k4_[i]);
    sys(t + T::c5 * h, y, k5_);
    for (std::size_t i = 0; i < n; ++i)
      y_[i] = x[i] + h * (T::a61 * k1_[i] + T::a62 * k2_[i] + T::a63 * k3_[i] + T::a64 * k4_[i] +
                          T::a65 * k5_[i]);
    const S t_end = t + h;
    sys(t_end, y, k6_);
    if (comp) {
      for (std::size_t i = 0; i < n; ++i) {
        const S inc = h * (T::b1 * k1_[i] + T::b3 * k3_[i] + T::b4 * k4_[i] + T::b5 * k5_[i] + T::b6 * k6_[i]) - comp[i];
        y_[i] = x[i] + inc;
        comp_new[i] = (y_[i] - x[i]) - inc;
      }
    } else {
      for (std::size_t i = 0; i < n; ++i)
        y_[i] = x[i] + h * (T::b1 * k1_[i] + T::b3 * k3_[i] + T::b4 * k4_[i] + T::b5 * k5_[i] + T::b6 * k6_[i]);
    }
    sys(t_end, y, k7_);
    rhs_evals_ += 6;
  }

  void resize(std::size_t n) {
    if (k1_.size() == n) return;
    for (State<S>* v : {&k1_, &k2_, &k3_, &k4_, &k5_, &k6_, &k7_, &y_, &err_, &r1_, &r2_, &r3_, &r4_, &r5_})
      v->assign(n, S(0));
    dense_valid_ = false;
  }

  State<S> k1_, k2_, k3_, k4_, k5_, k6_, k7_, y_, err_;
  State<S> r1_, r2_, r3_, r4_, r5_;  // dense-output coefficients of the last accepted step
  S t_old_ = S(0), t_new_ = S(0), h_old_ = S(0);
  bool dense_valid_ = false;
  std::size_t rhs_evals_ = 0;
};

// Dormand-Prince 5(4) under the controller of Hairer's DOPRI5 (PI control, StepAdjuster's defaults).
template <class S>
class Dopri5 : public ControlledStepper<Dopri5ErrorStepper<S>> {
 public:
  using Settings = typename StepAdjuster<S>::Settings;

  explicit Dopri5(Settings settings = {}) : ControlledStepper<Dopri5ErrorStepper<S>>({}, settings) {}
};

static_assert(ErrorStepper<Dopri5ErrorStepper<double>> && AdaptiveStepper<Dopri5<double>> &&
              DenseOutputStepper<Dopri5<double>>);
static_assert(AdaptiveStepper<Dopri5<long double>> && DenseOutputStepper<Dopri5<long double>>);

}  // namespace eomc::runtime
