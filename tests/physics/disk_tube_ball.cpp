// The seed example (Mei 1988, Fig. 1-1): q̈ = Ω² q, so from rest q(t) = q0 cosh(Ω t).
//   * Dopri5, templated over double and long double: the global error stays inside the bound
//     propagated from the accepted steps' tolerances (physics_support.hpp), and long double at a
//     tolerance 1e5 times tighter ends up far more accurate than double can be.
//   * Rk4 at fixed steps: the error falls by 2⁴ = 16 per halving of h.
#define BOOST_TEST_MODULE physics_disk_tube_ball
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <vector>

#include "disk_tube_ball.hpp"
#include "physics_support.hpp"

using Model = eomc::models::DiskTubeBall;
namespace rt = eomc::runtime;

namespace {

template <class S>
std::vector<S> exact(S t, S q0, S Omega) {
    using std::cosh;
    using std::sinh;
    return {q0 * cosh(Omega * t), q0 * Omega * sinh(Omega * t)};
}

struct Result {
    double error = 0;   // max over components of |x − exact| / |exact| at t1
    double bound = 0;   // the same for the derived bound
};

template <class S>
Result run_dopri5(rt::Tolerances tol) {
    using std::abs;
    phys::KernelSystem<Model, S> sys;
    const S q0 = S(1) / S(10), t1 = 2, Omega = S(sys.p.Omega);
    std::vector<S> x0{q0, 0};
    std::vector<S> x = x0;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, x, S(0), t1, tol);
    const auto bound = phys::propagated_error_bound<Model, S>(steps, x0, S(0), sys.p, tol);
    const auto ref = exact(t1, q0, Omega);
    Result r;
    for (int i = 0; i < 2; ++i) {
        const S err = abs(x[i] - ref[i]);
        BOOST_TEST_INFO("component " << i << ": |x - exact| = " << double(err) << ", bound " << double(bound[i])
                                     << ", steps " << steps.size());
        BOOST_TEST(err <= bound[i]);
        r.error = std::max(r.error, double(err / abs(ref[i])));
        r.bound = std::max(r.bound, double(bound[i] / abs(ref[i])));
    }
    return r;
}

}  // namespace

using Scalars = boost::mpl::list<double, long double>;

BOOST_AUTO_TEST_CASE_TEMPLATE(cosh_solution_with_dopri5, S, Scalars) {
    const Result r = run_dopri5<S>(rt::Tolerances{1e-10, 1e-12});
    BOOST_TEST_MESSAGE("rtol 1e-10: relative error " << r.error << ", derived bound " << r.bound);
}

// Long double at rtol 1e-15 (below double's ε = 2.2e-16 times the step count, which is what
// limits a double run): the derived bound scales with the tolerance, so the error must come out
// below double's error at 1e-10 by orders of magnitude and below the bound at 1e-15.
BOOST_AUTO_TEST_CASE(long_double_reaches_a_smaller_error) {
    const Result d = run_dopri5<double>(rt::Tolerances{1e-10, 1e-12});
    const Result ld = run_dopri5<long double>(rt::Tolerances{1e-15, 1e-17});
    BOOST_TEST_MESSAGE("double @1e-10: " << d.error << " (bound " << d.bound << "); long double @1e-15: " << ld.error
                                         << " (bound " << ld.bound << ")");
    BOOST_TEST(ld.error < d.error * 1e-3);
    // And double cannot get there at all: asked for 1e-15 it stays above long double's error,
    // because its rounding (ε per step, ~1e-16 × step count) is above that.
    const Result d_tight = run_dopri5<double>(rt::Tolerances{1e-15, 1e-17});
    BOOST_TEST_MESSAGE("double @1e-15: " << d_tight.error);
    BOOST_TEST(ld.error < d_tight.error);
}

// Classical RK4 has global error C h⁴ + O(h⁵): halving h divides it by 16 (1 + O(h)). The only
// time scale is 1/Ω, so the relative O(h) correction is of order Ω h; over the h used here
// (Ω h ≤ 0.06) the ratio must lie within 16 (1 ± Ω h) of 16, and approach 16 as h shrinks.
BOOST_AUTO_TEST_CASE(rk4_error_ratio_per_halving) {
    using S = double;
    phys::KernelSystem<Model, S> sys;
    const S q0 = 0.1, t1 = 2, Omega = sys.p.Omega;
    const auto ref = exact(t1, q0, Omega);
    std::vector<double> errors, hs;
    for (int steps : {100, 200, 400, 800}) {
        rt::Rk4<S> stepper;
        std::vector<S> x{q0, 0};
        const S h = t1 / steps;
        rt::integrate_fixed(stepper, sys, x, S(0), t1, h, [](S, const rt::State<S>&) {});
        errors.push_back(std::abs(x[0] - ref[0]));
        hs.push_back(h);
    }
    for (std::size_t k = 1; k < errors.size(); ++k) {
        const double ratio = errors[k - 1] / errors[k];
        const double allowed = 16 * Omega * hs[k - 1];
        BOOST_TEST_MESSAGE("h = " << hs[k - 1] << " -> " << hs[k] << ": error " << errors[k - 1] << " -> " << errors[k]
                                  << ", ratio " << ratio << " (16 +- " << allowed << ")");
        BOOST_TEST(std::abs(ratio - 16) <= allowed);
        // The errors are far above rounding (ε·q ≈ 4e-15), so the ratio measures truncation.
        BOOST_TEST(errors[k] > 1e3 * std::numeric_limits<double>::epsilon() * std::abs(ref[0]));
    }
}
