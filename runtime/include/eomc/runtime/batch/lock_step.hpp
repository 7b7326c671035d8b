#pragma once

// Lock-step integration of a batch of W systems, one per SIMD lane: a generated kernel's rhs with
// the scalar S a Lanes<W> (and its parameters one value per lane, Basic<Name><Lanes<W>>) runs W
// ensemble members per call, as heyoka's batch mode does. Both drivers step every lane with the
// same t and h:
//  - integrate_rk4_batch: the classical RK4 on integrate_fixed's grid (step k ends at t0 + k h, the
//    last one lands on t1) with Rk4's arithmetic, so that each lane is, bit for bit, the run of
//    that member alone (lane-wise IEEE operations; the <cmath> functions of std::experimental::simd
//    are the scalar ones lane by lane);
//  - integrate_dopri5_batch: Dormand–Prince 5(4) with one step size for the batch, chosen by the
//    scalar controller (StepAdjuster, [HNW] Sect. II.4) from the largest of the lanes' error norms,
//    and the smallest of their initial steps: each lane meets the tolerances, on a step sequence at
//    least as fine as its own. With W equal lanes it is the scalar Dopri5 run, bit for bit.
// A lane whose state (or error) stops being finite is dropped from the batch's control and marked
// failed in `alive`; the others go on. The caller reruns failed members alone for their diagnosis.

#include <experimental/simd>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "eomc/runtime/control/step_adjuster.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"

namespace eomc::runtime::batch {

template <std::size_t W>
using Lanes = std::experimental::fixed_size_simd<double, W>;

// One Lanes<W> per state component: x[i][k] is component i of lane k.
template <std::size_t W>
using BatchState = std::vector<Lanes<W>>;

// Lanes still integrated: false once a lane's state or error was not finite.
template <std::size_t W>
using Alive = std::experimental::fixed_size_simd_mask<double, W>;

template <std::size_t W>
Alive<W> finite_lanes(const BatchState<W>& x) {
  Alive<W> ok(true);
  for (const auto& v : x) ok = ok && std::experimental::isfinite(v);
  return ok;
}

// A batch system: sys(t, x, dxdt) over BatchState<W>, every lane at time t.
template <class Sys, std::size_t W>
concept BatchSystem = requires(Sys& sys, double t, const BatchState<W>& x, BatchState<W>& dxdt) { sys(t, x, dxdt); };

struct BatchStats {
  std::size_t accepted = 0, rejected = 0, rhs_evals = 0;
};

// RK4 from t0 to t1 in steps h (h of the sign of t1 − t0, non-zero: the caller checked), on
// integrate_fixed's grid. observer(t, x, alive) at t0 and after every step.
template <std::size_t W, class Sys, class Obs>
  requires BatchSystem<Sys, W>
BatchStats integrate_rk4_batch(Sys& sys, BatchState<W>& x, double t0, double t1, double h, Alive<W>& alive,
                               Obs&& observer) {
  using L = Lanes<W>;
  BatchStats stats;
  const std::size_t n = x.size();
  alive = alive && finite_lanes<W>(x);
  observer(t0, static_cast<const BatchState<W>&>(x), static_cast<const Alive<W>&>(alive));
  if (t0 == t1) return stats;
  BatchState<W> k1(n), k2(n), k3(n), k4(n), y(n);
  const double dir = t1 > t0 ? 1.0 : -1.0;
  const double land = 8.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t0), std::abs(t1));
  double t = t0;
  for (std::size_t k = 1;; ++k) {
    double t_next = t0 + static_cast<double>(k) * h;
    const bool last = (t_next - t1) * dir >= -land;
    if (last) t_next = t1;
    const double step = t_next - t;
    const L h_(step), h2(step / 2.0), h6(step / 6.0);
    const double half = step / 2.0;
    sys(t, static_cast<const BatchState<W>&>(x), k1);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h2 * k1[i];
    sys(t + half, static_cast<const BatchState<W>&>(y), k2);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h2 * k2[i];
    sys(t + half, static_cast<const BatchState<W>&>(y), k3);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h_ * k3[i];
    sys(t + step, static_cast<const BatchState<W>&>(y), k4);
    for (std::size_t i = 0; i < n; ++i) x[i] += h6 * (k1[i] + L(2.0) * (k2[i] + k3[i]) + k4[i]);
    stats.rhs_evals += 4;
    ++stats.accepted;
    t = t_next;
    alive = alive && finite_lanes<W>(x);
    observer(t, static_cast<const BatchState<W>&>(x), static_cast<const Alive<W>&>(alive));
    if (last || none_of(alive)) break;
  }
  return stats;
}

// Why a lock-step adaptive batch stopped short of t1 (every lane then counts as failed).
struct BatchStop {
  bool stopped = false;
  double t = 0.0;
  const char* why = "";
};

// DOPRI5 from t0 to t1 with one step size for the batch; rtol/atol as Tolerances, the first step
// chosen as initial_step() does, lane by lane (the smallest). observer(t, x, alive) at t0 and after
// every accepted step. max_attempts bounds the attempts (as Limits::max_steps), the step underflows
// as NoProgressChecker's does (16 eps max(|t|, |h_first|)).
template <std::size_t W, class Sys, class Obs>
  requires BatchSystem<Sys, W>
BatchStats integrate_dopri5_batch(Sys& sys, BatchState<W>& x, double t0, double t1, const Tolerances& tol,
                                  std::size_t max_attempts, Alive<W>& alive, BatchStop& stop, Obs&& observer) {
  using L = Lanes<W>;
  using T = DormandPrinceTableau<double>;
  namespace stdx = std::experimental;
  BatchStats stats;
  const std::size_t n = x.size();
  alive = alive && finite_lanes<W>(x);
  observer(t0, static_cast<const BatchState<W>&>(x), static_cast<const Alive<W>&>(alive));
  if (t0 == t1 || n == 0) return stats;
  const double dir = t1 > t0 ? 1.0 : -1.0, hmax = std::abs(t1 - t0);
  const L rtol(tol.rtol), atol(tol.atol);
  BatchState<W> k1(n), k2(n), k3(n), k4(n), k5(n), k6(n), k7(n), y(n), x1(n);
  // The lanes' largest value among those alive (0 when none is).
  const auto largest = [&](const L& v) {
    L w = v;
    where(!alive, w) = L(0.0);
    return stdx::hmax(w);
  };
  sys(t0, static_cast<const BatchState<W>&>(x), k1);
  ++stats.rhs_evals;

  // initial_step() lane by lane ([HNW] Sect. II.4, "Starting step size"), the smallest alive.
  double h;
  {
    L d0(0.0), d1(0.0), d2(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const L sc = atol + rtol * stdx::abs(x[i]);
      d0 += (x[i] / sc) * (x[i] / sc);
      d1 += (k1[i] / sc) * (k1[i] / sc);
    }
    d0 = stdx::sqrt(d0 / L(double(n)));
    d1 = stdx::sqrt(d1 / L(double(n)));
    L h0 = L(0.01) * d0 / d1;
    where(d0 < L(1e-5) || d1 < L(1e-5), h0) = L(1e-6);
    where(h0 > L(hmax), h0) = L(hmax);
    // Each lane's trial Euler step is its own h0: the lanes' own values, as alone.
    for (std::size_t i = 0; i < n; ++i) x1[i] = x[i] + L(dir) * h0 * k1[i];
    // The system takes one t for the batch: the trial step is evaluated lane by lane at t0 + dir h0
    // only where all lanes share h0; otherwise at each lane's time in turn.
    BatchState<W> f1(n);
    bool shared = true;
    for (std::size_t k = 1; k < W; ++k) shared = shared && h0[k] == h0[0];
    if (shared) {
      sys(t0 + dir * h0[0], static_cast<const BatchState<W>&>(x1), f1);
      ++stats.rhs_evals;
    } else {
      BatchState<W> fk(n);
      for (std::size_t k = 0; k < W; ++k) {
        sys(t0 + dir * h0[k], static_cast<const BatchState<W>&>(x1), fk);
        ++stats.rhs_evals;
        for (std::size_t i = 0; i < n; ++i) f1[i][k] = fk[i][k];
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const L sc = atol + rtol * stdx::abs(x[i]);
      d2 += ((f1[i] - k1[i]) / sc) * ((f1[i] - k1[i]) / sc);
    }
    d2 = stdx::sqrt(d2 / L(double(n))) / h0;
    const L dmax = stdx::max(d1, d2);
    L h1 = stdx::pow(L(0.01) / dmax, L(1.0 / 5.0));  // error order 4
    const L small = stdx::max(h0 * L(1e-3), L(1e-6));
    where(dmax <= L(1e-15), h1) = small;
    L hl = stdx::min(L(100.0) * h0, h1);
    where(!stdx::isfinite(d2), hl) = h0;
    where(hl > L(hmax), hl) = L(hmax);
    where(!alive, hl) = L(hmax);
    h = stdx::hmin(hl);
  }
  const double h_ref = std::abs(h);
  h *= dir;
  StepAdjuster<double> adjuster(4);
  std::size_t attempts = 0;
  double t = t0;
  for (;;) {
    const double scale = std::abs(t) > h_ref ? std::abs(t) : h_ref;
    if (std::abs(h) < 16.0 * std::numeric_limits<double>::epsilon() * scale) {
      stop = {true, t, "step size underflow"};
      return stats;
    }
    if (attempts++ >= max_attempts) {
      stop = {true, t, "step budget exhausted"};
      return stats;
    }
    if (std::abs(h) > hmax) h = dir * hmax;
    const bool last = (t + h - t1) * dir >= 0.0;
    if (last) h = t1 - t;
    const L hl(h);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + hl * L(T::a21) * k1[i];
    sys(t + T::c2 * h, static_cast<const BatchState<W>&>(y), k2);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + hl * (L(T::a31) * k1[i] + L(T::a32) * k2[i]);
    sys(t + T::c3 * h, static_cast<const BatchState<W>&>(y), k3);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + hl * (L(T::a41) * k1[i] + L(T::a42) * k2[i] + L(T::a43) * k3[i]);
    sys(t + T::c4 * h, static_cast<const BatchState<W>&>(y), k4);
    for (std::size_t i = 0; i < n; ++i)
      y[i] = x[i] + hl * (L(T::a51) * k1[i] + L(T::a52) * k2[i] + L(T::a53) * k3[i] + L(T::a54) * k4[i]);
    sys(t + T::c5 * h, static_cast<const BatchState<W>&>(y), k5);
    for (std::size_t i = 0; i < n; ++i)
      y[i] = x[i] + hl * (L(T::a61) * k1[i] + L(T::a62) * k2[i] + L(T::a63) * k3[i] + L(T::a64) * k4[i] +
                          L(T::a65) * k5[i]);
    const double t_end = t + h;
    sys(t_end, static_cast<const BatchState<W>&>(y), k6);
    for (std::size_t i = 0; i < n; ++i)
      y[i] = x[i] + hl * (L(T::b1) * k1[i] + L(T::b3) * k3[i] + L(T::b4) * k4[i] + L(T::b5) * k5[i] +
                          L(T::b6) * k6[i]);
    sys(t_end, static_cast<const BatchState<W>&>(y), k7);
    stats.rhs_evals += 6;
    // ErrorChecker::norm lane by lane: the RMS of e_i / (atol + rtol max(|x_i|, |y_i|)).
    L sum(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const L e = hl * (L(T::e1) * k1[i] + L(T::e3) * k3[i] + L(T::e4) * k4[i] + L(T::e5) * k5[i] +
                        L(T::e6) * k6[i] + L(T::e7) * k7[i]);
      const L sc = atol + rtol * stdx::max(stdx::abs(x[i]), stdx::abs(y[i]));
      L r = e / sc;
      where(sc <= L(0.0), r) = L(0.0);
      where(sc <= L(0.0) && e != L(0.0), r) = L(std::numeric_limits<double>::infinity());
      sum += r * r;
    }
    const L err_lanes = stdx::sqrt(sum / L(double(n)));
    // A lane whose error is not finite leaves the batch (alone it would shrink the step until it
    // underflows, or fail on its state).
    alive = alive && stdx::isfinite(err_lanes) && finite_lanes<W>(y) && finite_lanes<W>(k7);
    if (none_of(alive)) return stats;
    const double err = largest(err_lanes);
    if (err <= 1.0) {
      ++stats.accepted;
      for (std::size_t i = 0; i < n; ++i) x[i] = y[i];
      k1.swap(k7);  // first same as last
      t = last ? t1 : t_end;
      observer(t, static_cast<const BatchState<W>&>(x), static_cast<const Alive<W>&>(alive));
      if (last) return stats;
      h *= adjuster.accepted(err, h);
    } else {
      ++stats.rejected;
      h *= adjuster.rejected(err);
    }
  }
}

}  // namespace eomc::runtime::batch
