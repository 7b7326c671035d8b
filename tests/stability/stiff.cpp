// Stiff problems must stop cleanly: y' = −λ (y − cos t), λ = 10⁶, y(0) = 1 (on the slow manifold
// y ≈ cos t + sin t/λ). Explicit methods are stability-limited to |hλ| ≲ 3, so:
//  * Dopri5 with a small step budget throws IntegrationError::step_budget (message naming the
//    budget) instead of looping or returning NaN. Its accepted steps cannot exceed the edge of
//    its stability region by much (an unstable step grows the error, which the estimate sees), so
//    after the budget of B attempts it has advanced at most B·h_s, h_s = 3.3/λ (Dopri5's region
//    reaches −3.3 on the negative axis); we allow 3·B·h_s. The accepted states stay on the slow
//    manifold: |y − cos t| ≤ 1/λ (the manifold's offset) + √n·sc (one step's accepted error; the
//    stiff mode damps older ones).
//  * RK4 at h = 10⁻⁵ (hλ = −10, outside its interval [−2.785, 0]) amplifies the deviation by
//    |R(hλ)| = |1 + z + z²/2 + z³/6 + z⁴/24| = 291 per step; integrate_fixed must throw
//    non_finite when the state overflows, never hand NaN to the observer. The deviation starts
//    between ε (rounding) and 1 and the stages hold at most |λ||z|³ times it, so overflow
//    (DBL_MAX) comes after k steps with
//        (ln DBL_MAX − ln(2|λ||z|³)) / ln|R| − 1 ≤ k ≤ ln(DBL_MAX/ε) / ln|R| + 2.
#define BOOST_TEST_MODULE stability_stiff
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include <eomc/runtime/runtime.hpp>

namespace rt = eomc::runtime;

namespace {

constexpr double lambda = 1e6;

struct Stiff {
    void operator()(double t, const rt::State<double>& y, rt::State<double>& dy) const {
        dy[0] = -lambda * (y[0] - std::cos(t));
    }
};

}  // namespace

BOOST_AUTO_TEST_CASE(dopri5_stops_at_step_budget) {
    Stiff sys;
    rt::Dopri5<double> stepper;
    rt::State<double> y{1.0};
    const rt::Tolerances tol{1e-8, 1e-10};
    rt::Limits limits;
    limits.max_steps = 1000;
    double t_last = 0, worst_manifold = 0;
    bool all_finite = true;
    std::size_t observed = 0;
    bool threw = false;
    try {
        rt::integrate_adaptive(stepper, sys, y, 0.0, 1.0, 0.0, tol, [&](double t, const rt::State<double>& ys) {
            all_finite = all_finite && std::isfinite(ys[0]) && std::isfinite(t);
            worst_manifold = std::max(worst_manifold, std::abs(ys[0] - std::cos(t)));
            t_last = t;
            ++observed;
        }, limits);
    } catch (const rt::IntegrationError& err) {
        threw = true;
        const double h_s = 3.3 / lambda;
        BOOST_TEST_MESSAGE("Dopri5: " << err.what() << "; " << observed << " states observed, last t = " << t_last
                                      << " (bound " << 3 * 1000 * h_s << "), max |y - cos t| = " << worst_manifold);
        BOOST_TEST((err.kind() == rt::IntegrationError::Kind::step_budget));
        BOOST_TEST(std::string(err.what()).find("step budget of 1000 steps") != std::string::npos, err.what());
        BOOST_TEST(err.t() >= t_last);
        BOOST_TEST(err.t() <= 3 * 1000 * h_s);
        BOOST_TEST(observed <= 1001u);  // t0 plus at most one accepted step per attempt
    }
    BOOST_TEST(threw);
    BOOST_TEST(all_finite);
    BOOST_TEST(std::isfinite(y[0]));
    BOOST_TEST(worst_manifold <= 1 / lambda + std::sqrt(1.0) * (tol.atol + tol.rtol * 1.0));
}

BOOST_AUTO_TEST_CASE(rk4_beyond_stability_throws_non_finite) {
    Stiff sys;
    rt::Rk4<double> stepper;
    rt::State<double> y{1.0};
    const double h = 1e-5, z = -lambda * h;
    const double R = std::abs(1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24);
    const double lnmax = std::log(std::numeric_limits<double>::max());
    const double k_min = (lnmax - std::log(2 * lambda * std::abs(z * z * z))) / std::log(R) - 1;
    const double k_max = (lnmax - std::log(std::numeric_limits<double>::epsilon())) / std::log(R) + 2;
    std::size_t observed = 0;
    bool all_finite = true, threw = false;
    try {
        rt::integrate_fixed(stepper, sys, y, 0.0, 1.0, h, [&](double, const rt::State<double>& ys) {
            all_finite = all_finite && std::isfinite(ys[0]);
            ++observed;
        });
    } catch (const rt::IntegrationError& err) {
        threw = true;
        const double k = std::round(err.t() / h);
        BOOST_TEST_MESSAGE("Rk4: " << err.what() << " after step " << k << " (bounds " << k_min << " .. " << k_max
                                   << ", |R| = " << R << ")");
        BOOST_TEST((err.kind() == rt::IntegrationError::Kind::non_finite));
        BOOST_TEST(std::string(err.what()).find("non-finite state") != std::string::npos, err.what());
        BOOST_TEST(err.component() == 0u);
        BOOST_TEST(k >= k_min);
        BOOST_TEST(k <= k_max);
        BOOST_TEST(observed == std::size_t(k));  // t0 and steps 1 .. k−1; step k is the one that overflowed
    }
    BOOST_TEST(threw);
    BOOST_TEST(all_finite);
}
