// Collision: the bundled polar Kepler kernel with zero angular momentum (φ̇ = 0), falling from
// rest at r0 = 1 (μ = 1) into r = 0 at the free-fall time t_ff = (π/2)·√(r0³/(2μ)) = π/(2√2).
// The integration must end in an IntegrationError (step_underflow, or non_finite should a stage
// land on r = 0), with the observer having seen finite states only, at a time within a derived
// distance of t_ff:
//  * The collision time predicted from a state, P(t, x) = t + t_rem(r, ṙ), is conserved by the
//    exact flow (radial Kepler: r = A(1 − cos η), t = √(A³/μ)(η − sin η), A = μ/(2μ/r − ṙ²); the
//    collision is at η = 2π, so t_rem = √(A³/μ)(φ − sin φ), φ = 2π − η). As for any invariant, its
//    drift is bounded by Σ_steps Σ_i |∂P/∂x_i|(√n·sc_i + 4ε|x_i|) (physics_support.hpp), so the
//    last accepted state predicts t_ff within that bound ΔP.
//  * The step underflows when h < 16 ε t (Limits). Near the collision the solution's time scale
//    is the remaining fall time itself (r ∝ t_rem^(2/3)), so the controller's step is
//    h ≈ κ t_rem with κ ≥ 0.2·(tol/10³)^(1/5) (the same argument as the pericentre bound of
//    kepler_eccentric.cpp); the underflow therefore comes when t_rem ≤ 16 ε t_ff / κ.
//    Hence t_last ≤ t_ff + ΔP and t_last ≥ t_ff − ΔP − 16 ε t_ff/κ, and the error's t is t_last.
#define BOOST_TEST_MODULE stability_collision
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <vector>

#include "kepler_orbit.hpp"
#include "physics_support.hpp"

namespace rt = eomc::runtime;
using Model = eomc::models::KeplerOrbit;
using Vec = std::vector<double>;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double mu = 1;

// Remaining time to r = 0 along the exact radial orbit through (r, ṙ) (bound orbit, ṙ ≤ 0 or
// outgoing: φ ∈ (0, 2π)).
double t_rem(double r, double rdot) {
    const double A = mu / (2 * mu / r - rdot * rdot);
    const double s = rdot * r / std::sqrt(mu * A);  // sin η
    const double c = 1 - r / A;                     // cos η
    double phi = std::atan2(-s, c);                 // 2π − η
    if (phi < 0) phi += 2 * pi;
    // φ − sin φ without cancellation for small φ.
    const double f = phi < 1e-2 ? phi * phi * phi / 6 * (1 - phi * phi / 20 * (1 - phi * phi / 42)) : phi - std::sin(phi);
    return std::sqrt(A * A * A / mu) * f;
}

// Gradient of t_rem by central differences. Near the collision 2μ/r and ṙ² are huge and nearly
// cancel in w = 2μ/r − ṙ² = μ/A, so the steps are chosen to change w by 10⁻⁴ of itself (far
// above its rounding, ε·2μ/r ≲ 10⁻⁶ w here, and keeping the orbit bound).
std::array<double, 4> grad_t_rem(const Vec& x) {
    const double r = x[0], v = x[2], w = 2 * mu / r - v * v;
    const double hr = std::min(1e-4 * r, 1e-4 * w * r * r / (2 * mu));
    const double hv = 1e-4 * w / (2 * (std::abs(v) + std::sqrt(w)));
    std::array<double, 4> g{};
    g[0] = (t_rem(r + hr, v) - t_rem(r - hr, v)) / (2 * hr);
    g[2] = (t_rem(r, v + hv) - t_rem(r, v - hv)) / (2 * hv);
    return g;
}

void fall(double tol_value) {
    const rt::Tolerances tol{tol_value, tol_value};
    const double r0 = 1;
    const double t_ff = pi / 2 * std::sqrt(r0 * r0 * r0 / (2 * mu));
    phys::KernelSystem<Model, double> sys;
    rt::Dopri5<double> stepper;
    rt::State<double> x{r0, 0, 0, 0};
    BOOST_TEST(std::abs(t_rem(r0, 0) - t_ff) <= 4 * eps * t_ff);

    bool all_finite = true, first = true;
    double t_last = 0, dP = 0;
    Vec x_prev = x, x_last = x;
    std::size_t steps = 0;
    bool threw = false;
    try {
        rt::integrate_adaptive(stepper, sys, x, 0.0, 2.0, 0.0, tol, [&](double t, const rt::State<double>& xs) {
            for (double v : xs) all_finite = all_finite && std::isfinite(v);
            if (!first) {
                const auto lb = phys::local_error_bound(x_prev, xs, tol);
                const auto g = grad_t_rem(xs);
                for (int i = 0; i < 4; ++i) dP += std::abs(g[i]) * lb[i];
                ++steps;
            }
            first = false;
            x_prev = xs;
            t_last = t;
            x_last = xs;
        });
    } catch (const rt::IntegrationError& err) {
        threw = true;
        const double kappa = 0.2 * std::pow(tol_value / 1e3, 1.0 / 5);
        const double P_last = t_last + t_rem(x_last[0], x_last[2]);
        const double bP = dP + 16 * eps * t_ff;  // + rounding of t and of evaluating P
        const double below = bP + 16 * eps * t_ff / kappa;
        BOOST_TEST_MESSAGE("tol " << tol_value << ": " << err.what() << " after " << steps << " steps; t_err - t_ff = "
                                  << err.t() - t_ff << " (bounds -" << below << " .. +" << bP << "), last r = " << x_last[0]
                                  << ", t_rem = " << t_rem(x_last[0], x_last[2]) << ", |P - t_ff| = "
                                  << std::abs(P_last - t_ff) << " (bound " << bP << ")");
        BOOST_TEST((err.kind() == rt::IntegrationError::Kind::step_underflow ||
                    err.kind() == rt::IntegrationError::Kind::non_finite),
                   err.what());
        BOOST_TEST(err.t() == t_last);
        BOOST_TEST(std::abs(P_last - t_ff) <= bP);
        BOOST_TEST(err.t() <= t_ff + bP);
        BOOST_TEST(err.t() >= t_ff - below);
        BOOST_TEST(x_last[0] > 0);
        BOOST_TEST(x_last[2] < 0);
    }
    BOOST_TEST(threw);
    BOOST_TEST(all_finite);
}

}  // namespace

BOOST_AUTO_TEST_CASE(radial_fall_stops_at_free_fall_time) {
    fall(1e-10);
    fall(1e-12);
}
