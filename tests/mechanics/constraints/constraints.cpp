// [[constraint]] rows through the library (Mei, §6.6 and ch. 3; Lur'e, Analytical Mechanics,
// ch. 2; Chetaev 1932 for the kinematic rows): W and bias of a holonomic and a kinematic row
// compared as GiNaC expressions, the closed-form multiplier of the Cartesian pendulum against
// −m(l θ̇² + g cos θ)/(2l), the energy integral kept for scleronomic homogeneous rows and
// dropped for a rheonomic one, the refusals at file:line:column, and the printed derivation.
#define BOOST_TEST_MODULE mechanics_constraints
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <sstream>
#include <string>

#include <ginac/ginac.h>

#include "mechanics/constraints/constraints.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

#include "scenes.hpp"

using GiNaC::ex;
using eomc::InputError;
using eomc::model::Model;

namespace {

Model from_string(const std::string& toml) { return test_support::model_of(toml, "c.toml"); }

const GiNaC::symbol& symbol_named(const Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    for (const auto& c : model.coordinates) {
        if (c.name == name) return c.q;
        if (c.name + "_dot" == name) return c.q_dot;
    }
    BOOST_FAIL("no symbol " << name);
    return model.t;
}

bool same(const ex& a, const ex& b) { return GiNaC::normal((a - b).expand()).is_zero(); }

// The Cartesian pendulum, x = l sin θ, y = −l cos θ, with the initial state exactly on the rod
// (a 3-4-5 triangle, the velocity along the tangent).
std::string exact_pendulum(const std::string& row = "x^2 + y^2 - l^2", const std::string& extra = "") {
    return R"(
[scene]
name = "cartesian_pendulum"

[parameters]
m = 2.0
l = 5.0
g = 9.81
a = 0.25

[coordinates]
x = { initial = 3.0, rate = 0.8 }
y = { initial = -4.0, rate = 0.6 }

[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"

[[constraint]]
name = "rod"
holonomic = ")" + row + "\"\n" + extra;
}

const std::string sleigh = R"(
[scene]
name = "knife_edge"

[parameters]
m = 1.0
J = 0.2

[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = { initial = 0.0, rate = 0.0 }
phi = { initial = 0.0, rate = 0.5 }

[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2 + J*phi_dot^2/2"
V = "0"

[[constraint]]
name = "blade"
kinematic = "-sin(phi)*x_dot + cos(phi)*y_dot"
stabilize = { alpha = 10, beta = 10 }
)";

const std::string pendulum = exact_pendulum();

bool has_energy(const eomc::mechanics::Equations& eqs) {
    return std::any_of(eqs.invariants.begin(), eqs.invariants.end(), [](const auto& i) { return i.name == "energy"; });
}

// The InputError of building and deriving `toml`; fails the test when none is thrown.
InputError error_of(const std::string& toml) {
    try {
        const Model model = from_string(toml);
        (void)eomc::mechanics::derive(model);
    } catch (const InputError& e) {
        return e;
    }
    BOOST_FAIL("no InputError");
    return InputError({}, "");
}

}  // namespace

BOOST_AUTO_TEST_CASE(cartesian_pendulum_rows_and_multiplier) {
    const Model model = from_string(pendulum);
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.constraints.size(), 1u);
    const auto& row = eqs.constraints.front();
    const ex x = symbol_named(model, "x"), y = symbol_named(model, "y");
    const ex xd = symbol_named(model, "x_dot"), yd = symbol_named(model, "y_dot");
    const ex m = symbol_named(model, "m"), l = symbol_named(model, "l"), g = symbol_named(model, "g");
    BOOST_TEST(row.name == "rod");
    BOOST_TEST(row.holonomic);
    BOOST_TEST((row.stabilization == eomc::mechanics::Stabilization::project));
    BOOST_TEST(row.lambda.get_name() == "lambda_rod");
    BOOST_REQUIRE_EQUAL(row.W.size(), 2u);
    BOOST_TEST(same(row.W[0], 2 * x));
    BOOST_TEST(same(row.W[1], 2 * y));
    BOOST_TEST(same(row.velocity, 2 * x * xd + 2 * y * yd));
    BOOST_TEST(same(row.bias, 2 * xd * xd + 2 * yd * yd));
    BOOST_TEST(row.pos.line == 21);
    BOOST_TEST(row.pos.column == 14);
    // M, f stay those of the free system.
    BOOST_TEST(same(eqs.forcing[1], -m * g));
    // λ = −m(l θ̇² + g cos θ)/(2l) at x = l sin θ, y = −l cos θ, ẋ = l cos θ θ̇, ẏ = l sin θ θ̇.
    const auto lambda = eomc::mechanics::closed_form_multipliers(eqs);
    BOOST_REQUIRE(lambda);
    BOOST_REQUIRE_EQUAL(lambda->size(), 1u);
    const GiNaC::symbol th("theta"), thd("theta_dot");
    const GiNaC::exmap polar{{x, l * sin(th)}, {y, -l * cos(th)}, {xd, l * cos(th) * thd}, {yd, l * sin(th) * thd}};
    const ex expected = -m * (l * thd * thd + g * cos(th)) / (2 * l);
    const ex difference = ((*lambda)[0].subs(polar) - expected);
    BOOST_TEST(GiNaC::normal(difference.subs(pow(sin(th), 2) == 1 - pow(cos(th), 2)).expand()).is_zero(),
               "λ − expected = " << difference);
    // Energy T + V survives a scleronomic row; the first-order form carries the row.
    BOOST_TEST(has_energy(eqs));
    const auto form = eomc::mechanics::first_order_form(model, eqs);
    BOOST_REQUIRE_EQUAL(form.constraints.size(), 1u);
    BOOST_TEST(form.constraints.front().name == "rod");
}

BOOST_AUTO_TEST_CASE(knife_edge_kinematic_row) {
    const Model model = from_string(sleigh);
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.constraints.size(), 1u);
    const auto& row = eqs.constraints.front();
    const ex phi = symbol_named(model, "phi"), xd = symbol_named(model, "x_dot"), yd = symbol_named(model, "y_dot");
    const ex phid = symbol_named(model, "phi_dot");
    BOOST_TEST(!row.holonomic);
    BOOST_TEST(row.position.is_zero());
    BOOST_REQUIRE_EQUAL(row.W.size(), 3u);
    BOOST_TEST(same(row.W[0], -sin(phi)));
    BOOST_TEST(same(row.W[1], cos(phi)));
    BOOST_TEST(row.W[2].is_zero());
    // φ̇ − W q̈ = −cos φ φ̇ ẋ − sin φ φ̇ ẏ.
    BOOST_TEST(same(row.bias, -cos(phi) * phid * xd - sin(phi) * phid * yd));
    BOOST_TEST((row.stabilization == eomc::mechanics::Stabilization::baumgarte));
    BOOST_TEST(row.alpha == 10.0);
    BOOST_TEST(row.beta == 10.0);
    // Chetaev's ideal reactions of a homogeneous scleronomic row do no work: energy kept.
    BOOST_TEST(has_energy(eqs));
}

BOOST_AUTO_TEST_CASE(rheonomic_row_drops_energy) {
    // l + a t: the rod lengthens, its reaction does work (−λ ∂_t f ≠ 0).
    // The initial velocity gains the radial part a (x, y)/l so that ḟ(0) = 0.
    std::string toml = exact_pendulum("x^2 + y^2 - (l + a*t)^2");
    toml.replace(toml.find("rate = 0.8"), 10, "rate = 0.95");
    toml.replace(toml.find("rate = 0.6"), 10, "rate = 0.4");
    const auto eqs = eomc::mechanics::derive(from_string(toml));
    BOOST_REQUIRE_EQUAL(eqs.constraints.size(), 1u);
    BOOST_TEST(!has_energy(eqs));
    // The same scene with a fixed rod keeps it.
    BOOST_TEST(has_energy(eomc::mechanics::derive(from_string(exact_pendulum()))));
}

BOOST_AUTO_TEST_CASE(refusals) {
    {  // the initial state off the rod: the residual and the expression's place
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - 4*l^2"));
        BOOST_TEST(e.message().find("violates the constraint 'rod'") != std::string::npos, e.message());
        BOOST_TEST(e.message().find("-75") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:21:14", eomc::to_string(e.where()));
    }
    {  // on the rod but moving off it: φ = 2(x ẋ + y ẏ) = 2(2.4 + 2.4) ≠ 0
        std::string toml = exact_pendulum();
        toml.replace(toml.find("rate = 0.6"), 10, "rate = -0.6");
        const InputError e = error_of(toml);
        BOOST_TEST(e.message().find("violates") != std::string::npos, e.message());
        BOOST_TEST(e.message().find("9.6") != std::string::npos, e.message());
    }
    {  // quadratic in the rates
        std::string toml = sleigh;
        toml.replace(toml.find("-sin(phi)*x_dot + cos(phi)*y_dot"), 32, "x_dot^2 - y_dot^2 - 1");
        const InputError e = error_of(toml);
        BOOST_TEST(e.message().find("not linear in the rates") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:20:14", eomc::to_string(e.where()));
    }
    {  // a holonomic row with a rate
        const InputError e = error_of(exact_pendulum("x*x_dot + y*y_dot"));
        BOOST_TEST(e.message().find("x_dot") != std::string::npos, e.message());
        BOOST_TEST(e.where().line == 21);
    }
    {  // the same rod twice: dependent, both named
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2", "[[constraint]]\nname = \"rod2\"\nholonomic = \"2*(x^2 + y^2 - l^2)\"\n"));
        BOOST_TEST(e.message().find("'rod' and 'rod2' are dependent") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:21:14", eomc::to_string(e.where()));
    }
    {  // a row undefined at the initial state (GiNaC throws at log(0)): refused, not a crash
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2 + (x - 3)*log(x - 3)"));
        BOOST_TEST(e.message().find("does not evaluate to a real number at the initial state") != std::string::npos,
                   e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:21:14", eomc::to_string(e.where()));
    }
    {  // Baumgarte constants a double cannot hold as 2α and β² (CLN has no subnormals): refused at the number
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2", "stabilize = { alpha = 1e-310, beta = 1.0 }\n"));
        BOOST_TEST(e.message().find("'constraint[0].stabilize.alpha' must be 0 or between") != std::string::npos,
                   e.message());
        BOOST_TEST(e.where().line == 22);
        const InputError big = error_of(exact_pendulum("x^2 + y^2 - l^2", "stabilize = { alpha = 1.0, beta = 1e300 }\n"));
        BOOST_TEST(big.message().find("stabilize.beta' must be 0 or between") != std::string::npos, big.message());
    }
    {  // an unknown stabilize value
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2", "stabilize = \"projekt\"\n"));
        BOOST_TEST(e.message().find("unknown stabilize value 'projekt'") != std::string::npos, e.message());
        BOOST_TEST(e.message().find("did you mean 'project'") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:22:13", eomc::to_string(e.where()));
    }
    {  // duplicate names
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2", "[[constraint]]\nname = \"rod\"\nholonomic = \"x - 3\"\n"));
        BOOST_TEST(e.message().find("duplicate constraint name 'rod'") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:23:8", eomc::to_string(e.where()));
    }
    {  // both kinds in one row
        const InputError e = error_of(exact_pendulum("x^2 + y^2 - l^2", "kinematic = \"x_dot\"\n"));
        BOOST_TEST(e.message().find("both 'holonomic' and 'kinematic'") != std::string::npos, e.message());
    }
    {  // an orbit scene
        const InputError e = error_of(R"(
[scene]
name = "leo"

[parameters]
mu = 398600.4418
Re = 6378.137

[orbit]
central_body = { mu = "mu", radius = "Re" }
elements = { a = 7000.0, e = 0.01, i = 10.0 }

[[constraint]]
name = "plane"
holonomic = "z"
)");
        BOOST_TEST(e.message().find("not supported in an [orbit] scene") != std::string::npos, e.message());
        BOOST_TEST(eomc::to_string(e.where()) == "c.toml:15:14", eomc::to_string(e.where()));
    }
    {  // equilibria refuse a constrained scene
        const Model model = from_string(pendulum);
        const auto eqs = eomc::mechanics::derive(model);
        BOOST_CHECK_THROW(eomc::mechanics::relative_equilibria(model, eqs, {}), InputError);
    }
}

BOOST_AUTO_TEST_CASE(derivation_shows_constraints) {
    const Model model = from_string(pendulum);
    const auto eqs = eomc::mechanics::derive(model);
    std::ostringstream text, json, latex;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::json, json);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::latex, latex);
    const std::string t = text.str();
    BOOST_TEST_MESSAGE(t);
    BOOST_TEST(t.find("\nConstraints") != std::string::npos);
    BOOST_TEST(t.find("W = [2*x, 2*y]") != std::string::npos, t);
    // The reaction term per equation (GiNaC's term order is not fixed: look for the symbol on each line).
    for (const char* line : {"    s = x: ", "    s = y: "}) {
        const std::size_t at = t.find(line);
        BOOST_REQUIRE(at != std::string::npos);
        BOOST_TEST(t.substr(at, t.find('\n', at) - at).find("lambda_rod") != std::string::npos, t);
    }
    BOOST_TEST(t.find("Multipliers λ") != std::string::npos, t);
    BOOST_TEST(t.find("    lambda_rod = ") != std::string::npos, t);
    BOOST_TEST(t.find("Constraints") < t.find("\nInvariants"));
    const std::string j = json.str();
    BOOST_TEST(j.find("\"constraints\": [") != std::string::npos, j);
    BOOST_TEST(j.find("\"kind\": \"holonomic\"") != std::string::npos, j);
    BOOST_TEST(j.find("\"lambda\": ") != std::string::npos, j);
    BOOST_TEST(latex.str().find("\\subsection*{Constraints}") != std::string::npos);
    // Without constraints: no section.
    const Model free = test_support::bundled_model("double_pendulum");
    std::ostringstream plain;
    eomc::report::print_derivation(free, eomc::mechanics::derive(free), eomc::report::DerivationFormat::text, plain);
    BOOST_TEST(plain.str().find("Constraints") == std::string::npos);
}
