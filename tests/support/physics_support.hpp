// Shared pieces of the physics tests: a generated kernel as a runtime system, adaptive runs
// that keep a record of every accepted step, bounds on the global error derived from the
// tolerances those steps were accepted under, and turning points located on the dense output.
//
// The bounds. Dopri5 accepts a step when the weighted RMS norm of its error estimate is ≤ 1,
//   sqrt((1/n) Σ_i (e_i/sc_i)²) ≤ 1,  sc_i = atol + rtol·max(|x_old,i|, |x_new,i|),
// so every component of the estimated local error obeys |e_i| ≤ √n·sc_i. The estimate is that
// of the embedded fourth-order solution; the fifth-order solution that is propagated (local
// extrapolation) is more accurate, so √n·sc_i bounds its local error too as long as the steps
// are in the asymptotic regime (they are, at these tolerances). Rounding adds a few ulps of
// |x_i| per step (the update x + h Σ b_j k_j: 4 ε|x_i| covers it).
//   * An invariant I changes by at most |∇I|·|e| per step, so |I(x_N) − I(x_0)| is bounded by
//     Σ_steps Σ_i |∂I/∂x_i| (√n·sc_i + 4 ε |x_i|), plus the rounding of evaluating I twice.
//   * A state error propagates linearly, e(t1) = Φ(t1, t_k) e_k, with Φ the fundamental matrix of
//     the variational equation Φ̇ = J Φ (J: the generated Jacobian). So component i of the global
//     error is bounded by Σ_k Σ_j |Φ(t1, t_k)_ij| (√n·sc_k,j + 4 ε |x_k,j|).
// These bounds are conservative (the error estimate overestimates the fifth-order error, and
// errors of different steps partly cancel), but they are derived, and an O(1) mistake in the
// kernel (a wrong sign, a missing term) breaks them by many orders of magnitude.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include <eomc/runtime/runtime.hpp>

namespace phys {

namespace rt = eomc::runtime;

// A generated kernel as a runtime system (parameters default to the scene's values).
template <class Model, class S>
struct KernelSystem {
    typename Model::Parameters p{};
    void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const { Model::rhs(t, x.data(), dxdt.data(), p); }
};

template <class S>
struct Step {
    S t_old, t_new;
    std::vector<S> x_old, x_new;
    std::vector<S> local_bound;  // √n·sc_i + 4 ε |x_i|: bound on component i of the local error
};

template <class S>
std::vector<S> local_error_bound(const std::vector<S>& x_old, const std::vector<S>& x_new, const rt::Tolerances& tol) {
    using std::abs;
    const std::size_t n = x_old.size();
    const S root_n = std::sqrt(S(n));
    const S eps = std::numeric_limits<S>::epsilon();
    std::vector<S> b(n);
    for (std::size_t i = 0; i < n; ++i) {
        const S big = std::max(abs(x_old[i]), abs(x_new[i]));
        b[i] = root_n * (S(tol.atol) + S(tol.rtol) * big) + 4 * eps * big;
    }
    return b;
}

// Adaptive Dopri5 run from t0 to t1; every accepted step is recorded and handed to on_step(step,
// stepper) while the stepper's dense output still covers it.
template <class S, class Sys, class OnStep>
std::vector<Step<S>> run(rt::Dopri5<S>& stepper, Sys& sys, rt::State<S>& x, S t0, S t1, const rt::Tolerances& tol,
                         OnStep&& on_step) {
    std::vector<Step<S>> steps;
    bool first = true;
    S t_prev = t0;
    std::vector<S> x_prev = x;
    rt::integrate_adaptive(stepper, sys, x, t0, t1, S(0), tol, [&](S t, const rt::State<S>& xs) {
        if (!first) {
            Step<S> st{t_prev, t, x_prev, xs, local_error_bound(x_prev, xs, tol)};
            on_step(static_cast<const Step<S>&>(st), static_cast<const rt::Dopri5<S>&>(stepper));
            steps.push_back(std::move(st));
        }
        first = false;
        t_prev = t;
        x_prev = xs;
    });
    return steps;
}

template <class S, class Sys>
std::vector<Step<S>> run(rt::Dopri5<S>& stepper, Sys& sys, rt::State<S>& x, S t0, S t1, const rt::Tolerances& tol) {
    return run(stepper, sys, x, t0, t1, tol, [](const Step<S>&, const rt::Dopri5<S>&) {});
}

// Central-difference gradient of a scalar function of the state (only used inside bounds, where
// a relative error of 1e-8 is immaterial).
template <class S, class F>
std::vector<S> gradient(F&& f, const std::vector<S>& x) {
    using std::abs;
    std::vector<S> g(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        const S h = S(1e-5) * (1 + abs(x[i]));
        std::vector<S> xp = x, xm = x;
        xp[i] += h;
        xm[i] -= h;
        g[i] = (f(xp) - f(xm)) / (xp[i] - xm[i]);
    }
    return g;
}

// Bound on |I(x_end) − I(x_0)| from the recorded steps (see the header comment). `terms` is the
// magnitude of the largest term in I, for the rounding of evaluating I (32 ulps per evaluation).
template <class S, class F>
S invariant_drift_bound(const std::vector<Step<S>>& steps, F&& invariant, S terms) {
    using std::abs;
    S sum = 0;
    for (const auto& st : steps) {
        const auto g = gradient<S>(invariant, st.x_new);
        for (std::size_t i = 0; i < g.size(); ++i) sum += abs(g[i]) * st.local_bound[i];
    }
    return sum + 2 * 32 * std::numeric_limits<S>::epsilon() * terms;
}

// Component-wise bound on the global error at the end of a recorded run, by propagating every
// step's local error bound with Φ(t_end, t_k) = Φ(t_end, 0) Φ(t_k, 0)⁻¹. Φ(t_k, 0) comes from
// the variational equation along the recorded solution, integrated at a tolerance 100 times
// tighter than the run's (it only has to be accurate to a few digits).
template <class Model, class S>
std::vector<S> propagated_error_bound(const std::vector<Step<S>>& steps, const std::vector<S>& x0, S t0,
                                      const typename Model::Parameters& p, const rt::Tolerances& tol) {
    constexpr int n = Model::n_state;
    using Mat = Eigen::Matrix<S, n, n>;
    // z = (x, Φ column-major).
    auto variational = [&](S t, const rt::State<S>& z, rt::State<S>& dz) {
        Model::rhs(t, z.data(), dz.data(), p);
        S J[n * n];
        Model::jacobian(t, z.data(), J, p);
        for (int c = 0; c < n; ++c)
            for (int r = 0; r < n; ++r) {
                S sum = 0;
                for (int k = 0; k < n; ++k) sum += J[r * n + k] * z[n + c * n + k];
                dz[n + c * n + r] = sum;
            }
    };
    rt::State<S> z(n + n * n, S(0));
    for (int i = 0; i < n; ++i) {
        z[i] = x0[i];
        z[n + i * n + i] = 1;
    }
    std::vector<S> times{t0};
    for (const auto& st : steps) times.push_back(st.t_new);
    std::vector<Mat> phi;
    rt::Dopri5<S> stepper;
    rt::integrate_times(stepper, variational, z, times, S(0), rt::Tolerances{tol.rtol / 100, tol.atol / 100},
                        [&](S, const rt::State<S>& zs) {
                            Mat m;
                            for (int c = 0; c < n; ++c)
                                for (int r = 0; r < n; ++r) m(r, c) = zs[n + c * n + r];
                            phi.push_back(m);
                        });
    const Mat phi_end = phi.back();
    std::vector<S> bound(n, S(0));
    for (std::size_t k = 0; k < steps.size(); ++k) {
        const Mat from_k = phi_end * phi[k + 1].inverse();  // Φ(t_end, t_k)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) bound[i] += std::abs(from_k(i, j)) * steps[k].local_bound[j];
    }
    return bound;
}

// Root of g(t) on [a, b] (g(a), g(b) of opposite signs) by bisection down to a few ulps of t.
template <class S, class G>
S bisect(G&& g, S a, S b) {
    S ga = g(a);
    for (int it = 0; it < 200; ++it) {
        const S m = (a + b) / 2;
        if (m == a || m == b) break;
        const S gm = g(m);
        if ((gm > 0) == (ga > 0)) {
            a = m;
            ga = gm;
        } else {
            b = m;
        }
    }
    return (a + b) / 2;
}

// Times and states where g(x) crosses zero from positive to negative (g(x_old) > 0 ≥ g(x_new)
// on an accepted step), located on the step's dense output.
template <class S, class G>
struct DownCrossings {
    G g;
    std::vector<S> times;
    std::vector<std::vector<S>> states;
    void operator()(const Step<S>& st, const rt::Dopri5<S>& stepper) {
        if (!(g(st.x_old) > 0 && g(st.x_new) <= 0)) return;
        rt::State<S> buf;
        const S t = bisect<S>(
            [&](S tau) {
                stepper.calc_state(tau, buf);
                return g(buf);
            },
            st.t_old, st.t_new);
        stepper.calc_state(t, buf);
        times.push_back(t);
        states.push_back(buf);
    }
};

template <class S, class G>
DownCrossings<S, G> down_crossings(G g) {
    return DownCrossings<S, G>{std::move(g), {}, {}};
}

}  // namespace phys
