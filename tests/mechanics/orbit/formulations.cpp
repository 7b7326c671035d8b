// The orbit formulations of an orbit scene checked symbolically, before any integration:
//   * Newton's law: every formulation but mean, its Cartesian state X, V (cowell: the state;
//     the others: the kernel's outputs, functions of the state and, for encke's reference, of t)
//     moved along its own rates must give dX/dt = V and dV/dt = −μX/r³ + ∇R + a, the Cowell
//     acceleration, at every state — for the element formulations the defining property of
//     osculating elements. Checked at random states for a conservative perturbation (J2, J3,
//     J4, a third body) and a dissipative one (J2, drag, a custom acceleration), so that
//     Lagrange's equations in ∂R, Gauss's in ∇R + a, the canonical Delaunay equations, Encke's
//     deviation and Cowell's own each meet Newton's law, term by term;
//   * mean, which by design drops the short-period motion and so cannot meet Newton's law: R̄
//     of J2 is the closed form of Kozai (1959) and Brouwer (1959), and the secular rates are
//     their first-order mean rates Ω̇, ω̇, Ṁ;
//   * the classical elements' singularities: refused at e = 0 and i = 0, warned near them;
//   * the registry: each entry's kind, name and state names are those of the form it builds.
#define BOOST_TEST_MODULE orbit_formulations
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"

using GiNaC::ex;
namespace mech = eomc::mechanics;

namespace {

std::string scene_text(const std::string& formulation, const std::string& parameters, const std::string& effects,
                       const std::string& elements = "a = 7000.0, e = 0.01, i = 50.0") {
    return "[scene]\nname = \"s\"\n[parameters]\nmu = 398600.4418\nRe = 6378.137\n" + parameters +
           "[orbit]\ncentral_body = { mu = \"mu\", radius = \"Re\" }\nelements = { " + elements +
           " }\nformulation = \"" + formulation + "\"\n" + effects;
}

eomc::model::Model model_of(const std::string& toml) {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, "s.toml"));
}

const std::string zonal_and_moon =
    "J2 = 1.08262668e-3\nJ3 = -2.53265649e-6\nJ4 = -1.61962159e-6\nmu3 = 4902.800066\na3 = 384400\ni3 = 0.4\n";
const std::string conservative_effects = "[effects]\nkeep = [\"J2\", \"J3\", \"J4\", \"third_body\"]\n";
const std::string drag_parameters =
    "J2 = 1.08262668e-3\nrho0 = 3.614e-13\nh0 = 700\nH = 88.667\nCdA_m = 0.01\nomega = 7.2921159e-5\n";
// The custom acceleration: a small thrust along the velocity, so that all three Gauss
// components are exercised with something other than drag's form.
const std::string dissipative_effects = "[effects]\nkeep = [\"J2\", \"drag\"]\n[effects.custom]\n"
                                        "acceleration = [\"1e-9*x_dot\", \"1e-9*y_dot\", \"2e-9*z_dot + 1e-10*x\"]\n";

double number(const ex& e, const GiNaC::exmap& at) {
    const ex v = e.subs(at).evalf();
    BOOST_REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

GiNaC::exmap defaults(const eomc::model::Model& m) {
    GiNaC::exmap at;
    for (const auto& p : m.parameters) at[p.symbol] = GiNaC::numeric(p.value);
    return at;
}

// A random elliptic state of the formulation's variables: a in [7500, 20000] km, e from 0.05
// up to 0.6 or to a perigee 300 km above the surface (below it the atmosphere model's density
// grows like e^40 and the drag, not the check, would set the scale), i in [0.3, 2.8] rad, the
// angles anywhere.
GiNaC::exmap random_state(const mech::FirstOrderForm& form, double mu, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    const double a = 7500 + 12500 * u(rng), e_max = std::min(0.6, 1 - (6378.137 + 300) / a);
    const double e = 0.05 + (e_max - 0.05) * u(rng), i = 0.3 + 2.5 * u(rng);
    const double raan = 2 * std::numbers::pi * u(rng), argp = 2 * std::numbers::pi * u(rng);
    const double M = 2 * std::numbers::pi * u(rng) - std::numbers::pi;
    std::vector<double> q;
    if (form.state[0].name == "x") {
        // Cartesian: the periapsis or apoapsis of that ellipse, turned by the angles, at its speed there.
        const double r = u(rng) < 0.5 ? a * (1 - e) : a * (1 + e), v = std::sqrt(mu * (2 / r - 1 / a));
        const double cO = std::cos(raan), sO = std::sin(raan), ci = std::cos(i), si = std::sin(i);
        const double cw = std::cos(argp), sw = std::sin(argp);
        const double P[] = {cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si};
        const double Q[] = {-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si};
        q = {r * P[0], r * P[1], r * P[2], v * Q[0], v * Q[1], v * Q[2]};
    } else if (form.state[0].name == "dx") {
        // Encke: a reference ellipse with its epoch, and a deviation of up to 20 km and 20 m/s.
        q = {20 * (2 * u(rng) - 1),   20 * (2 * u(rng) - 1),   20 * (2 * u(rng) - 1), 0.02 * (2 * u(rng) - 1),
             0.02 * (2 * u(rng) - 1), 0.02 * (2 * u(rng) - 1), 1e5 * u(rng),           a,
             e,                       i,                       raan,                   argp,
             M,                       0};
    } else if (form.state[0].name == "l") {
        const double L = std::sqrt(mu * a), G = L * std::sqrt(1 - e * e);
        q = {M, argp, raan, L, G, G * std::cos(i)};
    } else if (form.state[0].name == "p") {
        // Modified equinoctial elements (orbital_elements.hpp's convention).
        const double p = a * (1 - e * e), t = std::tan(i / 2);
        const double nu = M;  // any true longitude will do: the state is random anyway
        q = {p, e * std::cos(argp + raan), e * std::sin(argp + raan), t * std::cos(raan), t * std::sin(raan),
             raan + argp + nu};
    } else {
        q = {a, e, i, raan, argp, M};
    }
    GiNaC::exmap at;
    for (std::size_t k = 0; k < q.size(); ++k) at[form.state[k].symbol] = GiNaC::numeric(q[k]);
    return at;
}

struct OsculationResidual {
    double position = 0, velocity = 0;  // worst |dX/dt − V|/|V| and |dV/dt − a|/(μ/r²)
};

// dX/dt and dV/dt of the formulation's Cartesian state along its rates, against V and the
// Cowell acceleration at the same Cartesian state, at `points` random states.
OsculationResidual osculation(const std::string& formulation, const std::string& parameters,
                              const std::string& effects, int points) {
    const auto model = model_of(scene_text(formulation, parameters, effects));
    const auto cowell = mech::derive(model);
    const auto form = mech::first_order_form(model, cowell);
    const auto& c = model.coordinates;
    const auto& o = *model.orbit;

    // Newton's acceleration in Cartesian variables, from the model itself.
    std::array<ex, 3> newton;
    for (std::size_t j = 0; j < 3; ++j)
        newton[j] = -o.mu * c[j].q / GiNaC::pow(o.r, 3) + eomc::symbolic::derivative(o.R, c[j].q) + o.acceleration[j];
    // The Cartesian state and its time derivative along the rates.
    std::array<ex, 6> cartesian, moved;
    if (form.outputs.empty()) {
        // Cowell: the state is (x, y, z, ẋ, ẏ, ż) and M u̇ = f with M = 1 (T = |v|²/2).
        BOOST_REQUIRE_EQUAL(form.state.size(), 6u);
        BOOST_REQUIRE_EQUAL(form.n_velocities(), 3u);
        for (std::size_t i = 0; i < 3; ++i)
            for (std::size_t j = 0; j < 3; ++j) BOOST_REQUIRE(form.mass_matrix(unsigned(i), unsigned(j)) == (i == j ? 1 : 0));
        for (std::size_t j = 0; j < 6; ++j) cartesian[j] = form.state[j].symbol;
        for (const auto& [k, rate] : form.explicit_rates) moved[k] = rate;
        for (std::size_t j = 0; j < 3; ++j) moved[3 + j] = form.forcing[j];
    } else {
        BOOST_REQUIRE_EQUAL(form.outputs.size(), 6u);
        for (std::size_t j = 0; j < 6; ++j) {
            cartesian[j] = form.outputs[j].value;
            moved[j] = eomc::symbolic::derivative(form.outputs[j].value, model.t);  // encke's reference moves with t
            for (const auto& [k, rate] : form.explicit_rates)
                moved[j] += eomc::symbolic::derivative(form.outputs[j].value, form.state[k].symbol) * rate;
        }
    }

    std::mt19937_64 rng(20261121);
    OsculationResidual worst;
    GiNaC::exmap base = defaults(model);
    const double mu = number(o.mu, base);
    for (int n = 0; n < points; ++n) {
        GiNaC::exmap at = random_state(form, mu, rng);
        at.insert(base.begin(), base.end());
        at[model.t] = GiNaC::numeric(1e5 * (n + 1));
        std::array<double, 6> cart{}, rates{};
        for (std::size_t j = 0; j < 6; ++j) {
            cart[j] = number(cartesian[j], at);
            rates[j] = number(moved[j], at);
        }
        GiNaC::exmap at_cart = base;
        at_cart[model.t] = at[model.t];
        for (std::size_t j = 0; j < 3; ++j) {
            at_cart[c[j].q] = GiNaC::numeric(cart[j]);
            at_cart[c[j].q_dot] = GiNaC::numeric(cart[j + 3]);
        }
        const double r = std::hypot(cart[0], cart[1], cart[2]), v = std::hypot(cart[3], cart[4], cart[5]);
        for (std::size_t j = 0; j < 3; ++j) {
            worst.position = std::max(worst.position, std::abs(rates[j] - cart[j + 3]) / v);
            worst.velocity = std::max(worst.velocity, std::abs(rates[j + 3] - number(newton[j], at_cart)) / (mu / (r * r)));
        }
    }
    return worst;
}

// The rounding floor of these checks: the outputs and their derivatives are evaluated in
// double-precision arithmetic (GiNaC's 17 digits; E from the runtime's solver, within half an
// ulp), through a few hundred operations whose terms reach |μ/r²| / (e sin i) before they
// cancel (ω̇ and Ṁ carry 1/e, Ω̇ 1/sin i; e ≥ 0.05, sin i ≥ 0.33 here, so a factor ≤ 60).
// 1e-11 of the scale is that factor times a few hundred ulps; an error in any perturbation
// term is of the size of J2 (1e-3) or of the drag (≥ 1e-9 of μ/r²) and shows far above it.
// Cowell's equations and Encke's deviation carry no such factor (their floor is a few ulps of
// μ/r²; Encke's reference ρ̈ comes through two derivatives of kepler_E, each 1/(1 − e cos E) ≤
// 1/(1 − 0.6)), so the same floor holds for them with room to spare.
constexpr double osculation_floor = 1e-11;

// Every formulation but mean (secular only, checked against its closed form below).
constexpr const char* newtonian_formulations[] = {"cowell", "encke", "gauss", "lagrange", "delaunay", "equinoctial"};

}  // namespace

BOOST_AUTO_TEST_CASE(conservative_perturbation_osculates) {
    for (const char* f : newtonian_formulations) {
        const auto worst = osculation(f, zonal_and_moon, conservative_effects, 6);
        BOOST_TEST_MESSAGE(f << ": dX/dt − V " << worst.position << ", dV/dt − a " << worst.velocity);
        BOOST_TEST_INFO(f);
        BOOST_TEST(worst.position <= osculation_floor);
        BOOST_TEST(worst.velocity <= osculation_floor);
    }
}

BOOST_AUTO_TEST_CASE(dissipative_perturbation_osculates) {
    // The custom acceleration is ~1e-6 of μ/r² at every state drawn, so a wrong sign or factor
    // in Gauss's terms shows far above the floor; drag reaches ~1e-6 only near a 300 km perigee
    // and is far smaller high up, so it is checked mainly at the low states.
    for (const char* f : newtonian_formulations) {
        const auto worst = osculation(f, drag_parameters, dissipative_effects, 6);
        BOOST_TEST_MESSAGE(f << ": dX/dt − V " << worst.position << ", dV/dt − a " << worst.velocity);
        BOOST_TEST_INFO(f);
        BOOST_TEST(worst.position <= osculation_floor);
        BOOST_TEST(worst.velocity <= osculation_floor);
    }
}

BOOST_AUTO_TEST_CASE(mean_j2_is_the_closed_form_average_and_gives_the_secular_rates) {
    const auto model = model_of(scene_text("mean", "J2 = 1.08262668e-3\n", "[effects]\nkeep = [\"J2\"]\n"));
    const auto form = mech::first_order_form(model, mech::derive(model));
    GiNaC::exmap at = defaults(model);
    const double mu = 398600.4418, Re = 6378.137, J2 = 1.08262668e-3;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (int n = 0; n < 8; ++n) {
        const double a = 6800 + 30000 * u(rng), e = 0.001 + 0.8 * u(rng), i = 0.05 + 3.0 * u(rng);
        const double raan = 6 * u(rng), argp = 6 * u(rng), M = 6 * u(rng);
        const double values[] = {a, e, i, raan, argp, M};
        for (std::size_t k = 0; k < 6; ++k) at[form.state[k].symbol] = GiNaC::numeric(values[k]);
        const double eta = std::sqrt(1 - e * e), p = a * eta * eta, nm = std::sqrt(mu / (a * a * a));
        const double ci = std::cos(i), si = std::sin(i), k2 = J2 * (Re / p) * (Re / p);
        // Kozai (1959), Brouwer (1959): the first-order secular rates of J2.
        const double R_bar = mu * J2 * Re * Re * (0.5 - 0.75 * si * si) / (a * a * a * eta * eta * eta);
        const double expected[] = {0, 0, 0, -1.5 * nm * k2 * ci, 0.75 * nm * k2 * (5 * ci * ci - 1),
                                   nm * (1 + 0.75 * k2 * eta * (3 * ci * ci - 1))};
        BOOST_TEST(form.derivation.front().name == "R_mean");
        BOOST_TEST(number(form.derivation.front().value, at) == R_bar, boost::test_tools::tolerance(1e-13));
        for (const auto& [k, rate] : form.explicit_rates) {
            BOOST_TEST_INFO(form.state[k].name << " at a = " << a << ", e = " << e << ", i = " << i);
            const double got = number(rate, at);
            // a, e and i have no secular rate under J2: exactly zero, not just small.
            if (k < 3) BOOST_TEST(got == 0.0);
            else BOOST_TEST(got == expected[k], boost::test_tools::tolerance(1e-12));
        }
    }
}

BOOST_AUTO_TEST_CASE(mean_refuses_what_it_cannot_average) {
    auto message = [](const std::string& toml) {
        try {
            const auto m = model_of(toml);
            mech::first_order_form(m, mech::derive(m));
        } catch (const eomc::InputError& e) {
            return e.message();
        }
        return std::string("no error");
    };
    BOOST_TEST(message(scene_text("mean", drag_parameters, "[effects]\nkeep = [\"J2\", \"drag\"]\n"))
                   .find("non-conservative acceleration") != std::string::npos);
    BOOST_TEST(message(scene_text("mean", "mu3 = 4902.8\na3 = 384400\ni3 = 0.4\n",
                                  "[effects]\nkeep = [\"third_body\"]\n"))
                   .find("closed form") != std::string::npos);
    // Falls off as 1/r: R·r² grows with r and has no polynomial average.
    BOOST_TEST(message(scene_text("mean", "k = 1\n", "[effects.custom]\ndisturbing_function = \"k/sqrt(x^2+y^2+z^2)\"\n"))
                   .find("closed form") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(classical_elements_are_refused_at_and_warned_near_their_singularities) {
    auto error_of = [](const std::string& toml) {
        try {
            model_of(toml);
        } catch (const eomc::InputError& e) {
            return eomc::to_string(e.where()) + ": " + e.message();
        }
        return std::string("no error");
    };
    const std::string j2 = "J2 = 1.08262668e-3\n", keep = "[effects]\nkeep = [\"J2\"]\n";
    for (const char* f : {"gauss", "lagrange", "delaunay", "mean"}) {
        BOOST_TEST_INFO(f);
        BOOST_TEST(error_of(scene_text(f, j2, keep, "a = 7000.0, e = 0.0, i = 50.0")).find(
                       "s.toml:10:15: the " + std::string(f) + " formulation's elements are singular for this orbit "
                       "(circular, e = 0)") == 0);
        BOOST_TEST(error_of(scene_text(f, j2, keep, "a = 8000.0, e = 0.1, i = 0.0")).find("(equatorial, sin i = 0)") !=
                   std::string::npos);
        const auto near = model_of(scene_text(f, j2, keep, "a = 7000.0, e = 0.0005, i = 50.0"));
        BOOST_REQUIRE_EQUAL(near.warnings.size(), 1u);
        BOOST_TEST(eomc::format_warning(near.warnings[0]).find("s.toml:10:15: warning: the " + std::string(f) +
                                                               " formulation's elements are nearly singular") == 0);
        BOOST_TEST(model_of(scene_text(f, j2, keep, "a = 7000.0, e = 0.01, i = 50.0")).warnings.empty());
    }
    // The equinoctial elements have no such trouble.
    BOOST_TEST(model_of(scene_text("equinoctial", j2, keep, "a = 7000.0, e = 0.0, i = 0.0")).warnings.empty());
    // A hyperbolic orbit has no elliptic Kepler solver to call.
    const auto hyperbolic = model_of(scene_text("lagrange", j2, keep, "a = -20000.0, e = 1.5, i = 30.0"));
    try {
        mech::first_order_form(hyperbolic, mech::derive(hyperbolic));
        BOOST_TEST(false, "a hyperbolic lagrange orbit was accepted");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.message().find("needs an elliptic orbit") != std::string::npos);
    }
}

BOOST_AUTO_TEST_CASE(the_registry_describes_what_each_formulation_builds) {
    const std::string j2 = "J2 = 1.08262668e-3\n", keep = "[effects]\nkeep = [\"J2\"]\n";
    BOOST_REQUIRE_EQUAL(mech::orbit_formulations().size(), eomc::scene::orbit_formulation_names.size());
    for (std::size_t k = 0; k < eomc::scene::orbit_formulation_names.size(); ++k) {
        const auto kind = static_cast<eomc::scene::OrbitFormulationKind>(k);
        const mech::OrbitFormulation& f = mech::orbit_formulation(kind);
        BOOST_TEST_INFO(eomc::scene::orbit_formulation_names[k]);
        BOOST_TEST((f.kind == kind));
        BOOST_TEST(f.name == eomc::scene::orbit_formulation_names[k]);
        const auto model = model_of(scene_text(std::string(f.name), j2, keep));
        const auto form = mech::first_order_form(model, mech::derive(model));
        std::vector<std::string> built, listed(f.state_names.begin(), f.state_names.end());
        for (const auto& s : form.state) built.push_back(s.name);
        BOOST_TEST(built == listed, boost::test_tools::per_element());
    }
    // Today only Cowell's state is (q, q̇), and only Encke's changes meaning along a run.
    using K = eomc::scene::OrbitFormulationKind;
    for (std::size_t k = 0; k < eomc::scene::orbit_formulation_names.size(); ++k) {
        const auto kind = static_cast<K>(k);
        BOOST_TEST(mech::hamiltonian_applies(kind) == (kind == K::cowell));
        BOOST_TEST(mech::variational_applies(kind) == (kind != K::encke));
    }
}
