#pragma once

// Gauss-Legendre implicit Runge-Kutta methods with s = 2, 3, 4 stages (orders 2s = 4, 6, 8):
// collocation at the zeros of the shifted Legendre polynomial P_s(2c - 1). They are symmetric,
// symplectic and conserve every quadratic first integral exactly (up to round-off), which makes
// them the methods of choice for long conservative runs with a fixed step. References:
//   [HW] Hairer-Wanner II, Sect. IV.5 (Table 5.1: the s = 2, 3 tableaux; Theorem 5.2: collocation);
//   [GNI] Hairer-Lubich-Wanner, Geometric Numerical Integration, 2nd ed.: Sect. VIII.5 (compensated
//     summation, Brouwer's law), Sect. VIII.6 (fixed-point iteration "until Delta_k = 0 or
//     Delta_k >= Delta_{k-1}", starting values from the previous step's collocation polynomial,
//     simplified Newton).
//
// The tableau is computed once per scalar type, in that scalar (so long double gets long double
// accuracy): c_i by Newton's method on the Legendre three-term recurrence, b_i by the Gauss weight
// formula b_i = 1 / ((1 - x_i^2) P_s'(x_i)^2) (x_i = 2c_i - 1, halved for [0, 1]), and a_ij from
// the collocation conditions a_ij = int_0^{c_i} l_j(tau) dtau, l_j the Lagrange basis on the c's.
// Closed forms (s = 2: c = 1/2 -+ sqrt(3)/6; s = 3: c = 1/2 -+ sqrt(15)/10, 1/2; s = 4: x =
// -+sqrt(3/7 -+ (2/7) sqrt(6/5))) are checked against this in tests/runtime_gauss.
//
// Stage equations, in the increments Z_i = Y_i - x_n = h sum_j a_ij K_j with K_j = f(t + c_j h, Y_j):
//  * fixed-point iteration Z <- h (A (x) I) F(x + Z) (every system), or
//  * simplified Newton (I - h A (x) J) dZ = -Z + h (A (x) I) F(x + Z), J = df/dx at (t, x_n),
//    factored once per step (systems with sys.jacobian(t, x, J), see HasJacobian), chosen
//    automatically unless GaussLegendreOptions::solver says otherwise.
// Both start from the previous step's collocation polynomial extrapolated to the new stage times
// (the first step starts from K_i = f(t, x)) and iterate to round-off: until the max-norm of the
// increment is zero or stops decreasing once below 1024 eps times the state's max-norm (a
// non-decrease above that is a transient, and iterating goes on). Failure to get there within
// max_iterations throws StageIterationError (an IntegrationError).
//
// The step is written as L_i = h b_i K_i, Z_i = sum_j mu_ij L_j, x_{n+1} = x_n + sum_i L_i with
// mu_ij = a_ij / b_j rounded so that mu_ij + mu_ji = 1 exactly (see GaussLegendreTableau::make):
// the method with the rounded coefficients is exactly symplectic, and quadratic invariants show
// no coefficient-induced linear drift (with plain a_ij, a 1000-period oscillator run in long double
// drifted by 730 eps; with mu, 12 eps).
//
// The update x_{n+1} = x_n + h sum_i b_i K_i uses compensated (Kahan) summation by default, so
// the round-off of a long run grows like a random walk (Brouwer's sqrt(n) law) instead of
// linearly. The stepper remembers the compensation and the last stages between steps; it detects
// a state or time changed behind its back (x differs from what it returned, or t from where it
// stopped) and then starts afresh, as after reset().

#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/jacobian.hpp"

namespace eomc::runtime {

// Thrown when the stage equations do not converge (step too large for the iteration, or a
// non-contracting system). Kind::step_budget: the iteration budget was exhausted.
class StageIterationError : public IntegrationError {
 public:
  template <class S>
  StageIterationError(S t, S h, int iterations, S last_increment)
      : IntegrationError(Kind::step_budget, static_cast<double>(t),
                         "Gauss-Legendre stage iteration did not converge at t = " + format(t) + " with h = " +
                             format(h) + " (" + std::to_string(iterations) + " iterations, last increment " +
                             format(last_increment) + "); reduce the step") {}
};

struct GaussLegendreOptions {
  enum class Solver { automatic, fixed_point, newton };
  // automatic: simplified Newton when the system has a Jacobian, fixed-point iteration otherwise.
  Solver solver = Solver::automatic;
  // Compensated (Kahan) summation of x_{n+1} = x_n + h sum b_i K_i.
  bool compensated = true;
  // Iterations allowed per step (each costs s system calls) before StageIterationError.
  int max_iterations = 100;
};

// Butcher tableau of the s-stage Gauss-Legendre method in scalar S, plus the coefficients of the
// Lagrange basis polynomials l_j(theta) = sum_m lagrange[j][m] theta^m on the nodes c.
template <class S, int Stages>
struct GaussLegendreTableau {
  static_assert(Stages >= 1 && Stages <= 8, "GaussLegendreTableau: 1 to 8 stages");
  std::array<S, Stages> c{}, b{};
  std::array<std::array<S, Stages>, Stages> a{}, lagrange{};
  // mu_ij = a_ij / b_j, rounded so that mu_ij + mu_ji = 1 holds exactly in S (see below).
  std::array<std::array<S, Stages>, Stages> mu{};

  static const GaussLegendreTableau& get() {
    static const GaussLegendreTableau t = make();
    return t;
  }

  // P_s(x) and P_s'(x) by the three-term recurrence (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
  static void legendre(S x, S& p, S& dp) {
    S p0 = S(1), p1 = x;
    for (int k = 1; k < Stages; ++k) {
      const S p2 = (S(2 * k + 1) * x * p1 - S(k) * p0) / S(k + 1);
      p0 = p1;
      p1 = p2;
    }
    p = p1;
    dp = S(Stages) * (x * p1 - p0) / (x * x - S(1));  // (x^2 - 1) P_s' = s (x P_s - P_{s-1})
  }

 private:
  static GaussLegendreTableau make() {
    using std::abs;
    using std::cos;
    GaussLegendreTableau t;
    const S pi = S(3.141592653589793238462643383279502884L);
    for (int i = 0; i < Stages; ++i) {
      // Root i of P_s in increasing order; the classical starting value (Abramowitz-Stegun 22.16.6)
      // is within the quadratic-convergence basin, so Newton settles in a handful of steps.
      S x = -cos(pi * (S(i) + S(0.75)) / (S(Stages) + S(0.5)));
      for (int it = 0; it < 100; ++it) {
        S p, dp;
        legendre(x, p, dp);
        const S dx = p / dp;
        x -= dx;
        if (abs(dx) <= std::numeric_limits<S>::epsilon() * S(0.5) * abs(x) || dx == S(0)) {
          // one more step at the limit of precision
          legendre(x, p, dp);
          x -= p / dp;
          break;
        }
      }
      S p, dp;
      legendre(x, p, dp);
      t.c[static_cast<std::size_t>(i)] = (S(1) + x) / S(2);
      t.b[static_cast<std::size_t>(i)] = S(1) / ((S(1) - x * x) * dp * dp);  // Gauss weight / 2
    }
    // Lagrange basis polynomials on the nodes c, expanded in monomials.
    for (std::size_t j = 0; j < Stages; ++j) {
      std::array<S, Stages> poly{};
      poly[0] = S(1);
      std::size_t deg = 0;
      for (std::size_t m = 0; m < Stages; ++m) {
        if (m == j) continue;
        const S inv = S(1) / (t.c[j] - t.c[m]);
        // poly <- poly * (theta - c_m) / (c_j - c_m)
        for (std::size_t k = deg + 1; k-- > 0;) {
          const S hi = poly[k] * inv;
          if (k + 1 < Stages) poly[k + 1] += hi;
          poly[k] = -t.c[m] * hi;
        }
        ++deg;
      }
      t.lagrange[j] = poly;
    }
    // a_ij = int_0^{c_i} l_j, by Horner on the antiderivative.
    for (std::size_t i = 0; i < Stages; ++i)
      for (std::size_t j = 0; j < Stages; ++j) {
        S acc = S(0);
        for (std::size_t k = Stages; k-- > 0;) acc = (acc + t.lagrange[j][k] / S(k + 1)) * t.c[i];
        t.a[i][j] = acc;
      }
    // Symplecticity b_i a_ij + b_j a_ji = b_i b_j is mu_ij + mu_ji = 1 with mu_ij = a_ij / b_j.
    // Rounded coefficients violate it by an ulp, which shows as a linear drift of quadratic
    // invariants over long runs; so, after Antonana, Makazaga, Murua ("Reducing and monitoring
    // round-off error propagation for symplectic implicit Runge-Kutta schemes", Numer. Algorithms
    // 76 (2017) 861-880), the step is written in mu and b, with mu_ii = 1/2 and, for each pair,
    // the member >= 1/2 rounded and the other set to 1 - it, which is exact (both 1 and mu are
    // multiples of ulp(mu) and |1 - mu| <= mu). The method with these rounded coefficients is then
    // exactly symplectic; only the arithmetic of the step rounds.
    for (std::size_t i = 0; i < Stages; ++i) {
      t.mu[i][i] = S(0.5);
      for (std::size_t j = 0; j < i; ++j) {
        const S mij = t.a[i][j] / t.b[j], mji = t.a[j][i] / t.b[i];
        if (mij >= mji) {
          t.mu[i][j] = mij;
          t.mu[j][i] = S(1) - mij;
        } else {
          t.mu[j][i] = mji;
          t.mu[i][j] = S(1) - mji;
        }
      }
    }
    return t;
  }
};

template <class S, int Stages>
class GaussLegendre {
 public:
  using value_type = S;
  using Options = GaussLegendreOptions;
  using Tableau = GaussLegendreTableau<S, Stages>;
  static constexpr int stages = Stages;
  static constexpr int order = 2 * Stages;

  GaussLegendre() = default;
  explicit GaussLegendre(const Options& options) : opt_(options) {}

  static const Tableau& tableau() { return Tableau::get(); }
  const Options& options() const { return opt_; }

  // Advances x from t to t + h in place.
  template <class Sys>
    requires System<Sys, S>
  void do_step(Sys& sys, State<S>& x, S t, S h) {
    using std::abs;
    using std::sqrt;
    const Tableau& tab = tableau();
    const std::size_t n = x.size();
    prepare(x, t, h, n);

    // Starting values for the stage derivatives K.
    if (have_history_) {
      const S r = h / h_prev_;
      for (std::size_t i = 0; i < Stages; ++i) {
        std::array<S, Stages> w{};
        const S theta = S(1) + tab.c[i] * r;
        for (std::size_t j = 0; j < Stages; ++j) {
          S acc = S(0);
          for (std::size_t m = Stages; m-- > 0;) acc = acc * theta + tab.lagrange[j][m];
          w[j] = acc;
        }
        for (std::size_t k = 0; k < n; ++k) {
          S acc = S(0);
          for (std::size_t j = 0; j < Stages; ++j) acc += w[j] * kprev_[j][k];
          k_[i][k] = acc;
        }
      }
    } else {
      for (std::size_t k = 0; k < n; ++k) y_[k] = x[k] - comp_[k];
      eval(sys, t, 0);
      for (std::size_t i = 1; i < Stages; ++i) k_[i] = k_[0];
    }
    stage_increments(h, n);
    for (std::size_t i = 0; i < Stages; ++i)
      for (std::size_t k = 0; k < n; ++k) {
        S acc = S(0);
        for (std::size_t j = 0; j < Stages; ++j) acc += tab.mu[i][j] * l_[j][k];
        z_[i][k] = acc;
      }

    bool newton = false;
    if constexpr (HasJacobian<Sys, S>) newton = opt_.solver != Options::Solver::fixed_point;
    if (opt_.solver == Options::Solver::newton && !newton)
      throw std::invalid_argument("GaussLegendre: Solver::newton needs a system with jacobian(t, x, J)");
    if constexpr (HasJacobian<Sys, S>)
      if (newton) factor(sys, x, t, h, n);

    S scale = S(0);
    for (std::size_t k = 0; k < n; ++k) scale = abs(x[k]) > scale ? abs(x[k]) : scale;
    if (!(scale > S(0))) scale = S(1);
    const S band = S(1024) * std::numeric_limits<S>::epsilon() * scale;

    S delta_prev = std::numeric_limits<S>::infinity();
    S delta = delta_prev;
    int it = 0;
    for (;;) {
      if (it >= opt_.max_iterations) throw StageIterationError(t, h, it, delta);
      ++it;
      ++iterations_;
      for (std::size_t i = 0; i < Stages; ++i) {
        for (std::size_t k = 0; k < n; ++k) y_[k] = x[k] + (z_[i][k] - comp_[k]);
        eval(sys, t + tab.c[i] * h, i);
      }
      delta = S(0);
      if (newton) {
        // residual -Z + h A F = -Z + mu L, then dZ = M^{-1} residual
        stage_increments(h, n);
        for (std::size_t i = 0; i < Stages; ++i)
          for (std::size_t k = 0; k < n; ++k) {
            S acc = S(0);
            for (std::size_t j = 0; j < Stages; ++j) acc += tab.mu[i][j] * l_[j][k];
            rhs_(static_cast<Eigen::Index>(i * n + k)) = acc - z_[i][k];
          }
        rhs_ = lu_.solve(rhs_);
        for (std::size_t i = 0; i < Stages; ++i)
          for (std::size_t k = 0; k < n; ++k) {
            const S d = rhs_(static_cast<Eigen::Index>(i * n + k));
            z_[i][k] += d;
            delta = abs(d) > delta ? abs(d) : delta;
          }
      } else {
        stage_increments(h, n);
        for (std::size_t i = 0; i < Stages; ++i)
          for (std::size_t k = 0; k < n; ++k) {
            S acc = S(0);
            for (std::size_t j = 0; j < Stages; ++j) acc += tab.mu[i][j] * l_[j][k];
            const S znew = acc;
            const S d = abs(znew - z_[i][k]);
            z_[i][k] = znew;
            delta = d > delta ? d : delta;
          }
      }
      if (!(delta == delta)) throw StageIterationError(t, h, it, delta);
      // Converged: nothing moves, or the increments stopped decreasing at round-off level.
      if (delta == S(0) || (delta >= delta_prev && delta_prev <= band)) break;
      delta_prev = delta;
    }

    // x_{n+1} = x_n + sum_i L_i, L_i = h b_i K_i, K from the last evaluation (consistent with Z to
    // round-off).
    stage_increments(h, n);
    for (std::size_t k = 0; k < n; ++k) {
      S inc = S(0);
      for (std::size_t i = 0; i < Stages; ++i) inc += l_[i][k];
      if (opt_.compensated) {
        const S y = inc - comp_[k];
        const S sum = x[k] + y;
        comp_[k] = (sum - x[k]) - y;
        x[k] = sum;
      } else {
        x[k] += inc;
      }
    }
    for (std::size_t i = 0; i < Stages; ++i) kprev_[i] = k_[i];
    h_prev_ = h;
    t_end_ = t + h;
    have_history_ = true;
    x_last_ = x;
  }

  // System calls made by this stepper since construction.
  std::size_t rhs_evals() const { return rhs_evals_; }
  // Stage iterations (fixed-point sweeps or Newton steps) since construction.
  std::size_t iterations() const { return iterations_; }
  // Jacobian evaluations (one per step on the Newton path) since construction.
  std::size_t jacobian_evals() const { return jacobian_evals_; }
  // Forgets the compensation and the previous step's stages.
  void reset() {
    have_history_ = false;
    x_last_.clear();
    comp_.assign(comp_.size(), S(0));
  }

 private:
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

  void prepare(const State<S>& x, S t, S h, std::size_t n) {
    if (y_.size() != n) {
      y_.assign(n, S(0));
      comp_.assign(n, S(0));
      for (std::size_t i = 0; i < Stages; ++i) {
        k_[i].assign(n, S(0));
        kprev_[i].assign(n, S(0));
        z_[i].assign(n, S(0));
        l_[i].assign(n, S(0));
      }
      have_history_ = false;
      x_last_.clear();
    }
    if (x != x_last_) {  // a new or edited state: the compensation belongs to another x
      comp_.assign(n, S(0));
      have_history_ = false;
    }
    using std::abs;
    // Extrapolate the previous collocation polynomial only when continuing where it ended and
    // not far beyond it (|h| <= 4 |h_prev|, same direction).
    if (have_history_ && (t != t_end_ || !(h / h_prev_ > S(0)) || abs(h) > S(4) * abs(h_prev_)))
      have_history_ = false;
  }

  // L_i = h b_i K_i; the stages are Z_i = sum_j mu_ij L_j (= h sum_j a_ij K_j).
  void stage_increments(S h, std::size_t n) {
    const Tableau& tab = tableau();
    for (std::size_t i = 0; i < Stages; ++i) {
      const S hb = h * tab.b[i];
      for (std::size_t k = 0; k < n; ++k) l_[i][k] = hb * k_[i][k];
    }
  }

  template <class Sys>
  void eval(Sys& sys, S ti, std::size_t i) {
    using std::isfinite;
    const State<S>& yc = y_;
    sys(ti, yc, k_[i]);
    ++rhs_evals_;
    for (std::size_t k = 0; k < k_[i].size(); ++k)
      if (!isfinite(k_[i][k])) throw IntegrationError::non_finite(ti, "stage derivative", k);
  }

  // M = I - h (A (x) J), J at (t, x_n), LU-factored for the simplified Newton iteration.
  template <class Sys>
  void factor(Sys& sys, const State<S>& x, S t, S h, std::size_t n) {
    const Tableau& tab = tableau();
    const auto N = static_cast<Eigen::Index>(n);
    jac_.setZero(N, N);
    sys.jacobian(t, x, jac_);
    ++jacobian_evals_;
    Matrix m = Matrix::Identity(N * Stages, N * Stages);
    for (std::size_t i = 0; i < Stages; ++i)
      for (std::size_t j = 0; j < Stages; ++j)
        m.block(static_cast<Eigen::Index>(i) * N, static_cast<Eigen::Index>(j) * N, N, N) -= (h * tab.b[j] * tab.mu[i][j]) * jac_;
    lu_.compute(m);
    rhs_.resize(N * Stages);
  }

  Options opt_{};
  std::array<State<S>, Stages> k_, kprev_, z_, l_;
  State<S> y_, comp_, x_last_;
  S h_prev_ = S(0), t_end_ = S(0);
  bool have_history_ = false;
  Matrix jac_;
  Vector rhs_;
  Eigen::PartialPivLU<Matrix> lu_;
  std::size_t rhs_evals_ = 0, iterations_ = 0, jacobian_evals_ = 0;
};

template <class S>
using Gl4 = GaussLegendre<S, 2>;
template <class S>
using Gl6 = GaussLegendre<S, 3>;
template <class S>
using Gl8 = GaussLegendre<S, 4>;

}  // namespace eomc::runtime
