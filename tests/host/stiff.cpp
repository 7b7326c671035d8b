// eomc simulate on a stiff scene (scenes/van_der_pol_stiff.toml, Van der Pol mu = 1000): radau5 on
// the kernel's Jacobian against a long double reference, and the stiffness hint of the explicit
// methods (stability-limited steps) that a non-stiff scene does not get.
#define BOOST_TEST_MODULE simulate_stiff
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <string>

#include "host/simulate.hpp"

#include "simulation.hpp"

using eomc::host::SimulationRequest;
using eomc::host::SimulationResult;
using eomc::host::simulate;

namespace {

const test_support::Kernel& van_der_pol() {
    static const test_support::Kernel k =
        test_support::kernel_of(test_support::bundled_scene("van_der_pol_stiff"), {.jacobian = true});
    return k;
}

SimulationRequest request(const test_support::Kernel& k, const std::string& integrator, double t_end, double tol) {
    SimulationRequest r = test_support::simulation_request(k, t_end);
    r.integrator = integrator;
    r.rtol = tol;
    r.atol = tol;
    return r;
}

}  // namespace

// The state at t = 3000 from (2, 0): radau5 in long double at rtol = atol = 1e-16 (bench/stiff_cvode.cpp;
// it differs from the run at 1e-14 by 5.6e-12). At rtol = atol = 1e-6 radau5 controls its
// estimate at rtol' = 0.1 rtol^{2/3} = 1e-5; the final state is on a slow branch (|x'| ~ 1e-3),
// where the phase error of a period shows as ~ rtol' |x| (the test in
// tests/runtime/stepper/radau5.cpp bounds the period by rtol' T): bound 10 rtol'.
BOOST_AUTO_TEST_CASE(radau5_reaches_the_reference_on_the_kernels_jacobian) {
    const SimulationResult r = simulate(request(van_der_pol(), "radau5", 3000.0, 1e-6));
    BOOST_TEST(r.t == 3000.0);
    const double bound = 10 * 0.1 * std::pow(1e-6, 2.0 / 3.0);
    BOOST_TEST(std::abs(r.value("x") - -1.5106069367441858) <= bound);
    BOOST_TEST(std::abs(r.value("x_dot") - 0.0011783800007307603) <= bound);
    // Stiff: ~500 steps where DOP853 takes ~875 000.
    BOOST_TEST(r.steps <= 2000u);
    BOOST_TEST_MESSAGE(r.integrator << ": " << r.steps << " steps, " << r.rhs_evals << " calls");
    BOOST_TEST(r.integrator.find("the kernel's symbolic Jacobian") != std::string::npos, r.integrator);
    BOOST_TEST(r.hint.empty());
}

// DOP853 on the slow branch (t in [0, 100]): every step at its stability boundary h |lambda| ~ 6,
// lambda ~ -mu (1 - x^2) ~ -3000; the summary names radau5. A non-stiff run (mu = 1: h |lambda| far
// below the boundary at this tolerance) gets no hint.
BOOST_AUTO_TEST_CASE(explicit_runs_get_the_stiffness_hint_only_when_stability_limited) {
    const SimulationResult stiff = simulate(request(van_der_pol(), "dop853", 100.0, 1e-6));
    BOOST_TEST_MESSAGE(stiff.hint);
    BOOST_TEST(stiff.hint.find("radau5") != std::string::npos);
    BOOST_TEST(stiff.hint.find("dop853's stability boundary") != std::string::npos);
    SimulationRequest mild = request(van_der_pol(), "dop853", 20.0, 1e-6);
    mild.overrides.push_back({"mu", 1.0});
    const SimulationResult calm = simulate(mild);
    BOOST_TEST(calm.hint.empty(), calm.hint);
}

// A kernel generated without jacobian(): radau5 falls back to forward differences, says so, and
// still reaches the same reference (the Newton matrix only steers the iteration; the bound is the
// one above).
BOOST_AUTO_TEST_CASE(radau5_without_the_kernels_jacobian_uses_finite_differences) {
    static const test_support::Kernel plain = test_support::kernel_of(test_support::bundled_scene("van_der_pol_stiff"));
    BOOST_TEST(plain.header.find("static void jacobian(") == std::string::npos);
    const SimulationResult r = simulate(request(plain, "radau5", 3000.0, 1e-6));
    BOOST_TEST(r.integrator.find("finite-difference Jacobian") != std::string::npos, r.integrator);
    const double bound = 10 * 0.1 * std::pow(1e-6, 2.0 / 3.0);
    BOOST_TEST(std::abs(r.value("x") - -1.5106069367441858) <= bound);
}
