// The lock-step batches (runtime/batch/lock_step.hpp) on the checked-in damped oscillator kernel,
// ẍ = −γẋ − w²x, whose rates are + − × only: every lane does the IEEE operations of the scalar
// run, so the batch must reproduce the scalar drivers bit for bit; and against the closed form.
#define BOOST_TEST_MODULE batch_lock_step
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "eomc/runtime/batch/lock_step.hpp"
#include "eomc/runtime/integrate.hpp"

#include "damped_oscillator.hpp"

namespace rb = eomc::runtime::batch;
namespace rt = eomc::runtime;
constexpr std::size_t W = 4;
using Lanes = rb::Lanes<W>;
using Scalar = eomc::models::DampedOscillator;
using Batched = eomc::models::BasicDampedOscillator<Lanes>;

namespace {

constexpr std::array<double, W> ws{0.5, 1.0, 1.7, 3.0};  // one w per lane

Batched::Parameters lane_parameters(const std::array<double, W>& w) {
    Batched::Parameters p;
    p.w = Lanes(w.data(), std::experimental::element_aligned);
    return p;
}

struct BatchSystem {
    Batched::Parameters p;
    void operator()(double t, const rb::BatchState<W>& x, rb::BatchState<W>& dxdt) const {
        Batched::rhs(Lanes(t), x.data(), dxdt.data(), p);
    }
};

struct ScalarSystem {
    Scalar::Parameters p;
    void operator()(double t, const rt::State<double>& x, rt::State<double>& dxdt) const {
        Scalar::rhs(t, x.data(), dxdt.data(), p);
    }
};

rb::BatchState<W> start() { return {Lanes(1.0), Lanes(0.0)}; }  // x = 1 at rest, every lane

// The underdamped closed form x(t) = e^{−γt/2}(cos ω_d t + γ/(2ω_d) sin ω_d t), ω_d² = w² − γ²/4.
double closed_form(double w, double t) {
    const double gamma = 0.1, wd = std::sqrt(w * w - gamma * gamma / 4);
    return std::exp(-gamma * t / 2) * (std::cos(wd * t) + gamma / (2 * wd) * std::sin(wd * t));
}

}  // namespace

BOOST_AUTO_TEST_CASE(rk4_lanes_are_the_scalar_runs_bit_for_bit) {
    BatchSystem sys{lane_parameters(ws)};
    rb::BatchState<W> x = start();
    rb::Alive<W> alive(true);
    std::size_t observed = 0;
    // t_end / h is not a whole number: the last step is shortened, as integrate_fixed's.
    const double t_end = 10.05, h = 0.1;
    const auto stats = rb::integrate_rk4_batch<W>(sys, x, 0.0, t_end, h, alive,
                                                  [&](double, const rb::BatchState<W>&, const rb::Alive<W>&) { ++observed; });
    BOOST_TEST(all_of(alive));
    for (std::size_t k = 0; k < W; ++k) {
        ScalarSystem one{Scalar::Parameters{}};
        one.p.w = ws[k];
        rt::State<double> y{1.0, 0.0};
        rt::Rk4<double> stepper;
        const auto s = rt::integrate_fixed(stepper, one, y, 0.0, t_end, h, [](double, const rt::State<double>&) {});
        BOOST_TEST_INFO("lane " << k);
        BOOST_TEST(double(x[0][k]) == y[0]);  // exactly
        BOOST_TEST(double(x[1][k]) == y[1]);
        BOOST_TEST(stats.accepted == s.accepted);
        // RK4's local error on ẋ = λx is |λh|⁵/120 relative (the first term of e^{λh} it misses),
        // |λ| = w here; over t_end/h steps that is t_end w⁵ h⁴ / 120, doubled for the damping.
        BOOST_TEST(std::abs(double(x[0][k]) - closed_form(ws[k], t_end)) < 2 * t_end * std::pow(ws[k], 5) * std::pow(h, 4) / 120);
    }
    BOOST_TEST(observed == stats.accepted + 1);
}

// With W equal lanes the batch's error norm is the scalar's, so the step sequence and the bits are
// those of integrate_adaptive with Dopri5.
BOOST_AUTO_TEST_CASE(dopri5_with_equal_lanes_is_the_scalar_run_bit_for_bit) {
    for (double w : ws) {
        BatchSystem sys{lane_parameters({w, w, w, w})};
        rb::BatchState<W> x = start();
        rb::Alive<W> alive(true);
        rb::BatchStop stop;
        const rt::Tolerances tol{1e-10, 1e-12};
        const auto stats = rb::integrate_dopri5_batch<W>(sys, x, 0.0, 20.0, tol, 1'000'000, alive, stop,
                                                         [](double, const rb::BatchState<W>&, const rb::Alive<W>&) {});
        ScalarSystem one{Scalar::Parameters{}};
        one.p.w = w;
        rt::State<double> y{1.0, 0.0};
        rt::Dopri5<double> stepper;
        const auto s = rt::integrate_adaptive(stepper, one, y, 0.0, 20.0, 0.0, tol, [](double, const rt::State<double>&) {});
        BOOST_TEST_INFO("w = " << w);
        BOOST_TEST(!stop.stopped);
        BOOST_TEST(stats.accepted == s.accepted);
        BOOST_TEST(stats.rejected == s.rejected);
        for (std::size_t k = 0; k < W; ++k) {
            BOOST_TEST(double(x[0][k]) == y[0]);
            BOOST_TEST(double(x[1][k]) == y[1]);
        }
    }
}

// Different lanes share the step of the most demanding one: each is at least as accurate as alone.
// Each accepted step's local error is below the tolerance (rtol 1e-10 on |x| ≤ 1); the contracting
// flow does not amplify it, so the global error is below (accepted steps) × 1e-10.
BOOST_AUTO_TEST_CASE(dopri5_lanes_meet_their_tolerances_against_the_closed_form) {
    BatchSystem sys{lane_parameters(ws)};
    rb::BatchState<W> x = start();
    rb::Alive<W> alive(true);
    rb::BatchStop stop;
    const auto stats = rb::integrate_dopri5_batch<W>(sys, x, 0.0, 20.0, rt::Tolerances{1e-10, 1e-12}, 1'000'000, alive,
                                                     stop, [](double, const rb::BatchState<W>&, const rb::Alive<W>&) {});
    BOOST_TEST(!stop.stopped);
    for (std::size_t k = 0; k < W; ++k) {
        BOOST_TEST_INFO("lane " << k);
        BOOST_TEST(std::abs(double(x[0][k]) - closed_form(ws[k], 20.0)) < static_cast<double>(stats.accepted) * 1e-10);
    }
}

// A lane that stops being finite leaves the batch; the others finish as if it were not there.
BOOST_AUTO_TEST_CASE(a_non_finite_lane_is_dropped_and_the_others_go_on) {
    BatchSystem sys{lane_parameters(ws)};
    rb::BatchState<W> x = start();
    x[0][2] = std::numeric_limits<double>::quiet_NaN();
    rb::Alive<W> alive(true);
    rb::BatchStop stop;
    rb::integrate_dopri5_batch<W>(sys, x, 0.0, 20.0, rt::Tolerances{1e-10, 1e-12}, 1'000'000, alive, stop,
                                  [](double, const rb::BatchState<W>&, const rb::Alive<W>&) {});
    BOOST_TEST(!stop.stopped);
    BOOST_TEST(!bool(alive[2]));
    for (std::size_t k : {0u, 1u, 3u}) {
        BOOST_TEST(bool(alive[k]));
        BOOST_TEST(std::abs(double(x[0][k]) - closed_form(ws[k], 20.0)) < 2e-7);
    }
}
