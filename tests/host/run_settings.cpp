// host::resolve_settings: a request's names resolved to the runtime's types once, every setting
// checked by one rule at the option or scene value that chose it, before anything is compiled;
// describe_method as the summaries print it; the programs' stiffness warning judged from the
// catalogue's stability data (RK4's polynomial, the explicit pairs' real boundary).
#define BOOST_TEST_MODULE host_run_settings
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "eomc/runtime/registry_info.hpp"
#include "host/simulate.hpp"
#include "support/diagnostic.hpp"

using eomc::InputError;
using eomc::SourcePos;
using eomc::host::resolve_settings;
using eomc::host::SimulationRequest;
namespace rc = eomc::runtime::contact;

namespace {

// The error resolve_settings throws for r, as "where: message".
std::string refusal(const SimulationRequest& r) {
    try {
        (void)resolve_settings(r);
    } catch (const InputError& e) {
        return eomc::to_string(e.where()) + ": " + e.message();
    }
    return "";
}

}  // namespace

BOOST_AUTO_TEST_CASE(defaults_resolve_to_the_catalogues_entries) {
    const SimulationRequest defaults;
    const auto s = resolve_settings(defaults);
    BOOST_TEST(s.method == eomc::runtime::find_integrator(eomc::runtime::default_integrator));
    BOOST_TEST(s.tolerances.rtol == 1e-10);
    BOOST_TEST(s.tolerances.atol == 1e-12);
    BOOST_TEST(!s.compensated);
    BOOST_TEST((s.contact_method == rc::ContactMethod::event_driven));
    BOOST_TEST((s.impact_law == rc::ImpactLaw::simultaneous));
    BOOST_TEST(eomc::host::describe_method(s) == "dopri5 (rtol 1e-10, atol 1e-12)");
}

BOOST_AUTO_TEST_CASE(names_resolve_through_the_tables) {
    SimulationRequest r;
    r.integrator = "gl6";
    r.step = 0.01;
    r.contact_method = "moreau_jean";
    r.impact_law = "sequential";
    const auto s = resolve_settings(r);
    BOOST_TEST(s.method->name == "gl6");
    BOOST_TEST(s.compensated);  // the symplectic fixed-step methods compensate by default
    BOOST_TEST((s.contact_method == rc::ContactMethod::moreau_jean));
    BOOST_TEST((s.impact_law == rc::ImpactLaw::sequential));
    BOOST_TEST(eomc::host::describe_method(s) == "gl6 (step 0.01, compensated)");
    BOOST_TEST(eomc::host::describe_method(s, false) == "gl6 (step 0.01)");
    r.compensated = false;
    BOOST_TEST(!resolve_settings(r).compensated);
}

BOOST_AUTO_TEST_CASE(each_setting_is_refused_at_its_place) {
    {
        SimulationRequest r;
        r.integrator = "dopri6";
        r.integrator_pos = SourcePos{"scene.toml", 12, 14};
        BOOST_TEST(refusal(r) == "scene.toml:12:14: unknown integrator 'dopri6'; did you mean 'dopri5'? (expected one of "
                                 "rk4, dopri5, dop853, radau5, gl4, gl6, gl8, verlet, yoshida6, kahanli8)");
    }
    {
        SimulationRequest r;
        r.contact_method = "moreau_jeans";
        BOOST_TEST(refusal(r).find("--contact-method: unknown contact method 'moreau_jeans'; did you mean 'moreau_jean'?") ==
                   0u);
    }
    {
        SimulationRequest r;
        r.impact_law = "serial";
        BOOST_TEST(refusal(r).find("--impact-law: unknown impact law 'serial'") == 0u);
    }
    // Lengths of time and tolerances: positive and finite, one rule.
    {
        SimulationRequest r;
        r.t_end = -1.0;
        BOOST_TEST(refusal(r).find("--t-end: the end time must be positive and finite") == 0u);
    }
    {
        SimulationRequest r;
        r.atol = 0.0;
        BOOST_TEST(refusal(r).find("--atol: the absolute tolerance must be positive and finite") == 0u);
        r.integrator = "rk4";  // a fixed-step method takes no tolerances, and its step instead
        BOOST_TEST(refusal(r).empty());
        r.step = std::numeric_limits<double>::infinity();
        BOOST_TEST(refusal(r).find("--step: the rk4 step must be positive and finite") == 0u);
    }
    // Moreau–Jean's θ in [1/2, 1] (the scene's rule).
    {
        SimulationRequest r;
        r.theta = 0.25;
        BOOST_TEST(refusal(r).find("theta must lie in [0.5, 1]") != std::string::npos);
    }
    // A fixed-step run's budget, before the compile.
    {
        SimulationRequest r;
        r.integrator = "rk4";
        r.step = 0.125;
        r.t_end = 1.0;
        r.max_steps = 7;
        BOOST_TEST(refusal(r).find("--step: rk4 with step 0.125 to t_end = 1 takes 8 steps, more than the budget of 7") ==
                   0u);
        r.max_steps = 8;
        BOOST_TEST(refusal(r).empty());
    }
}

// The catalogue's traits, as the runs read them.
BOOST_AUTO_TEST_CASE(the_catalogue_says_what_the_host_used_to_spell) {
    using eomc::runtime::find_integrator;
    BOOST_TEST(find_integrator("rk4")->batch);
    BOOST_TEST(find_integrator("dopri5")->batch);
    BOOST_TEST(!find_integrator("dop853")->batch);
    BOOST_TEST(find_integrator("dopri5")->real_stability_boundary == 3.3);
    BOOST_TEST(find_integrator("dop853")->real_stability_boundary == 6.1);
    BOOST_TEST(find_integrator("radau5")->implicit());
    BOOST_TEST(!find_integrator("radau5")->stability_limited());
    BOOST_TEST(find_integrator("gl4")->implicit());
    // RK4's real boundary is where its stored polynomial leaves the unit disc: |R(−2.78)| < 1 < |R(−2.79)|.
    const auto rk4 = [&](double z) {
        double r = 0.0;
        for (auto c = find_integrator("rk4")->stability_polynomial.rbegin();
             c != find_integrator("rk4")->stability_polynomial.rend(); ++c)
            r = r * z + *c;
        return std::abs(r);
    };
    BOOST_TEST(rk4(-2.78) < 1.0);
    BOOST_TEST(rk4(-2.79) > 1.0);
    BOOST_TEST(std::abs(rk4(-find_integrator("rk4")->real_stability_boundary) - 1.0) < 2e-3);
    BOOST_TEST(eomc::runtime::integrator_list([](const auto& i) { return i.symplectic && !i.needs_separable; }, ", ",
                                              " or ") == "gl4, gl6 or gl8");
}
