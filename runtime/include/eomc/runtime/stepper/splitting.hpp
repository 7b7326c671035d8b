#pragma once

// Symplectic splitting methods for separable second-order systems q'' = a(t, q) (H = T(p) + V(q)
// with a constant mass matrix, so the velocity is the momentum up to a constant matrix): the
// Stormer-Verlet method and symmetric compositions of it. References:
//   [GNI] Hairer-Lubich-Wanner, Geometric Numerical Integration, 2nd ed.: Sect. I.3.1 (Stormer-
//     Verlet), Sect. V.3.2 (symmetric compositions of a symmetric method, coefficient tables
//     (3.11) p6 s7 and (3.12) p8 s15), Sect. VIII.5 (compensated summation);
//   [Y90] H. Yoshida, Construction of higher order symplectic integrators, Phys. Lett. A 150 (1990)
//     262-268, "solution A" of the order-6, 7-stage composition;
//   [KL97] W. Kahan, R.-C. Li, Composition constants for raising the orders of unconventional
//     schemes for ordinary differential equations, Math. Comp. 66 (1997) 1089-1099, the order-8
//     15-stage composition (coefficients as printed in [GNI] (3.12)).
//
// State x = (q, v), n = x.size()/2 positions followed by their n velocities. The system is an
// acceleration callable acc(t, q, a) with q and a of size n (NOT the first-order right-hand side
// f(t, x, dxdt): both have the same signature, so the System concept of integrate_fixed accepts
// either; passing a first-order rhs here writes out of bounds).
//
// One Verlet step of size g h (kick-drift-kick, velocity Verlet):
//   v += (g h / 2) a(t, q);  q += g h v;  v += (g h / 2) a(t + g h, q).
// A composition of s Verlet steps with sizes gamma_1 h, ..., gamma_s h merges the adjacent half
// kicks (they use the same q and t), so a step is s + 1 kicks at s + 1 positions alternating with s
// drifts: kick coefficients b_0 = gamma_1/2, b_i = (gamma_i + gamma_{i+1})/2, b_s = gamma_s/2;
// drift i moves t by gamma_i h as well (time is treated as a position coordinate, which is what
// makes the method exact for a(t, q) that depends on t; for autonomous systems it is irrelevant).
// FSAL: the last kick's acceleration a(t + h, q_{n+1}) is the next step's first, so a step costs s
// acceleration evaluations instead of s + 1 when the next step continues from where this one
// stopped (same system object, x unchanged, t equal to the end time up to 4 ulps: integrate_fixed
// passes t_next - t as h, and t + h can miss t_next by an ulp).
//
// Compensated (Kahan) summation of every kick and drift, on by default (SplittingOptions::
// compensated): the low-order bits lost by each update are carried into the next one (and across
// steps), so the round-off of the state grows like a random walk in the increments' own errors
// instead of eps |x| per update. Like GaussLegendre, the stepper remembers the compensation and
// the FSAL acceleration between steps and drops both when x differs from what it returned last
// (or after reset()); a system whose parameters change between steps needs reset().

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "eomc/runtime/stepper/coefficients.hpp"
#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

struct SplittingOptions {
  // Compensated (Kahan) summation of the q and v updates.
  bool compensated = true;
  // Reuse the last acceleration of a step as the first of the next (first same as last).
  bool fsal = true;
};

// Composition coefficients gamma_i (sum 1), as decimal literals rounded once to the scalar
// (coefficients.hpp: long double for double and long double, all digits for float128).
struct VerletCoefficients {
  static constexpr int order = 2;
  static constexpr std::array<detail::Coefficient, 1> gamma{EOMC_COEFFICIENT(1.0)};
};

// [Y90] solution A, also [GNI] V.(3.11) "p6 s7" (digits from the 36-digit evaluation of [Y90]'s
// equations; w0 = 1 - 2 (w1 + w2 + w3)).
struct Yoshida6Coefficients {
  static constexpr int order = 6;
  static constexpr detail::Coefficient w1 = EOMC_COEFFICIENT(-1.17767998417887100694641568096431573);
  static constexpr detail::Coefficient w2 = EOMC_COEFFICIENT(0.235573213359358133684793182978534602);
  static constexpr detail::Coefficient w3 = EOMC_COEFFICIENT(0.784513610477557263819497633866349876);
  static constexpr detail::Coefficient w0 = EOMC_COEFFICIENT(1.31518632068391121888424972823886251);
  static constexpr std::array<detail::Coefficient, 7> gamma{w3, w2, w1, w0, w1, w2, w3};
};

// [KL97] s = 15, order 8, as printed in [GNI] V.(3.12) "p8 s15" (gamma_i = gamma_{16-i}; 26 digits,
// which bounds a float128 run's accuracy at about 1e-26).
struct KahanLi8Coefficients {
  static constexpr int order = 8;
  static constexpr detail::Coefficient g1 = EOMC_COEFFICIENT(0.74167036435061295344822780);
  static constexpr detail::Coefficient g2 = EOMC_COEFFICIENT(-0.40910082580003159399730010);
  static constexpr detail::Coefficient g3 = EOMC_COEFFICIENT(0.19075471029623837995387626);
  static constexpr detail::Coefficient g4 = EOMC_COEFFICIENT(-0.57386247111608226665638773);
  static constexpr detail::Coefficient g5 = EOMC_COEFFICIENT(0.29906418130365592384446354);
  static constexpr detail::Coefficient g6 = EOMC_COEFFICIENT(0.33462491824529818378495798);
  static constexpr detail::Coefficient g7 = EOMC_COEFFICIENT(0.31529309239676659663205666);
  static constexpr detail::Coefficient g8 = EOMC_COEFFICIENT(-0.79688793935291635401978884);
  static constexpr std::array<detail::Coefficient, 15> gamma{g1, g2, g3, g4, g5, g6, g7, g8,
                                                             g7, g6, g5, g4, g3, g2, g1};
};

template <class S, class Coefficients>
class Composition {
 public:
  using value_type = S;
  using coefficients = Coefficients;
  static constexpr int order = Coefficients::order;
  static constexpr std::size_t stages = Coefficients::gamma.size();

  explicit Composition(SplittingOptions options = {}) : opt_(options) {
    // Kicks and nodes are formed in long double and rounded once, or in S when S is wider.
    using W = std::conditional_t<detail::wider_than_long_double<S>, S, long double>;
    const auto& g = Coefficients::gamma;
    W c = W(0);
    for (std::size_t i = 0; i < stages; ++i) {
      const W gi = detail::coefficient<W>(g[i]);
      kick_[i] = S((i == 0 ? W(0) : detail::coefficient<W>(g[i - 1])) / W(2) + gi / W(2));
      drift_[i] = S(gi);
      c += gi;
      node_[i] = S(c);
    }
    kick_[stages] = S(detail::coefficient<W>(g[stages - 1]) / W(2));
  }

  // Advances x = (q, v) from t to t + h in place; acc(t, q, a) writes the n accelerations.
  template <class Acc>
    requires System<Acc, S>
  void do_step(Acc& acc, State<S>& x, S t, S h) {
    if (x.size() % 2 != 0)
      throw std::invalid_argument("splitting do_step: the state must be (q, v), of even size");
    const std::size_t n = x.size() / 2;
    prepare(x, n);
    using std::abs;
    const bool reuse = opt_.fsal && have_acc_ && acc_id_ == static_cast<const void*>(&acc) &&
                       abs(t - t_end_) <= S(4) * std::numeric_limits<S>::epsilon() * abs(t);
    const State<S>& qc = q_;
    if (!reuse) {
      acc(t, qc, a_);
      ++rhs_evals_;
    }
    const S t_end = t + h;
    for (std::size_t i = 0; i < stages; ++i) {
      const S kh = kick_[i] * h, dh = drift_[i] * h;
      for (std::size_t k = 0; k < n; ++k) add(x[n + k], kh * a_[k], comp_[n + k]);
      for (std::size_t k = 0; k < n; ++k) {
        add(x[k], dh * x[n + k], comp_[k]);
        q_[k] = x[k];
      }
      acc(i + 1 == stages ? t_end : t + node_[i] * h, qc, a_);
      ++rhs_evals_;
    }
    const S kh = kick_[stages] * h;
    for (std::size_t k = 0; k < n; ++k) add(x[n + k], kh * a_[k], comp_[n + k]);
    x_last_ = x;
    t_end_ = t_end;
    have_acc_ = true;
    acc_id_ = static_cast<const void*>(&acc);
  }

  // Acceleration evaluations made by this stepper since construction.
  std::size_t rhs_evals() const { return rhs_evals_; }
  // Forgets the compensation and the stored (FSAL) acceleration.
  void reset() {
    have_acc_ = false;
    x_last_.clear();
    comp_.assign(comp_.size(), S(0));
  }
  const SplittingOptions& options() const { return opt_; }

 private:
  void prepare(const State<S>& x, std::size_t n) {
    if (q_.size() != n) {
      q_.assign(n, S(0));
      a_.assign(n, S(0));
      comp_.assign(2 * n, S(0));
      have_acc_ = false;
      x_last_.clear();
    }
    if (x != x_last_) {  // a new or edited state: compensation and acceleration belong to another x
      comp_.assign(2 * n, S(0));
      have_acc_ = false;
    }
    for (std::size_t k = 0; k < n; ++k) q_[k] = x[k];
  }

  // x += inc, compensated: c holds minus the part of the previous increments lost in x.
  void add(S& x, S inc, S& c) const {
    if (opt_.compensated) {
      const S y = inc - c;
      const S s = x + y;
      c = (s - x) - y;
      x = s;
    } else {
      x += inc;
    }
  }

  SplittingOptions opt_;
  std::array<S, stages + 1> kick_{};
  std::array<S, stages> drift_{}, node_{};
  State<S> q_, a_, comp_, x_last_;
  S t_end_ = S(0);
  bool have_acc_ = false;
  const void* acc_id_ = nullptr;
  std::size_t rhs_evals_ = 0;
};

// Stormer-Verlet (velocity Verlet, kick-drift-kick), order 2, 1 evaluation per step with FSAL.
template <class S>
using Verlet = Composition<S, VerletCoefficients>;
// Yoshida's order-6 composition of Verlet (solution A), 7 evaluations per step with FSAL.
template <class S>
using Yoshida6 = Composition<S, Yoshida6Coefficients>;
// Kahan-Li order-8 composition of Verlet (s = 15), 15 evaluations per step with FSAL.
template <class S>
using KahanLi8 = Composition<S, KahanLi8Coefficients>;

}  // namespace eomc::runtime
