// [[unilateral]] rows through the library (Mei, ch. 6, §6.2–§6.7): W and bias of the bouncing
// ball's floor (W = (1), bias 0), the pendulum against a wall in its angle (W = (1)), the rod with an
// end on the floor (f = y − l sin θ: W = (0, 1, −l cos θ), bias = l sin θ θ̇²) and a velocity row
// ẏ ≥ 0 (§6.7), compared as GiNaC expressions; the first-order form carries them; the energy is
// kept between impacts only; the derivation's section in text, LaTeX and JSON (parsed back).
#define BOOST_TEST_MODULE mechanics_unilateral
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <ginac/ginac.h>

#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "mechanics/unilateral/unilateral.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

#include "scenes.hpp"

using GiNaC::ex;
using eomc::model::Model;

namespace {

Model from_string(const std::string& toml) { return test_support::model_of(toml, "u.toml"); }

// A bundled scene (scenes/<name>.toml).
Model from_file(const std::string& name) {
    return eomc::model::build_model(eomc::scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) +
                                                                  "/scenes/" + name + ".toml"));
}

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

const std::string rod = R"toml(
[scene]
name = "falling_rod"

[parameters]
m = 1.0
l = 0.5
J = 0.0833333333333333
g = 9.81

[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = 0.3, rate = -2.0 }
theta = { initial = 0.5235987755982988, rate = 0.0 }

[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2 + J*theta_dot^2/2"
V = "m*g*y"

[[unilateral]]
name = "end"
gap = "y - l*sin(theta)"
restitution = "0.5"
)toml";

const std::string ratchet = R"(
[scene]
name = "ratchet"

[parameters]
m = 1.0

[coordinates]
y = { initial = -1.0, rate = 0.0 }

[lagrangian]
T = "m*y_dot^2/2"
V = "2*m*y^2"

[[unilateral]]
name = "pawl"
velocity = "y_dot"
)";

bool has_energy(const eomc::mechanics::Equations& eqs) {
    return std::any_of(eqs.invariants.begin(), eqs.invariants.end(), [](const auto& i) { return i.name == "energy"; });
}

}  // namespace

BOOST_AUTO_TEST_CASE(bouncing_ball_floor) {
    const Model model = from_file("bouncing_ball");
    const auto rows = eomc::mechanics::unilateral_rows(model);
    BOOST_REQUIRE_EQUAL(rows.size(), 1u);
    const auto& r = rows.front();
    BOOST_TEST(r.row.name == "floor");
    BOOST_TEST(r.row.holonomic);
    BOOST_REQUIRE_EQUAL(r.row.W.size(), 1u);
    BOOST_TEST(same(r.row.W[0], 1));
    BOOST_TEST(r.row.bias.is_zero());
    BOOST_TEST(same(r.row.position, symbol_named(model, "y")));
    BOOST_TEST(same(r.row.velocity, symbol_named(model, "y_dot")));
    BOOST_TEST(same(r.restitution, symbol_named(model, "e")));
    BOOST_TEST(r.row.lambda.get_name() == "lambda_floor");
    BOOST_TEST(eomc::to_string(r.row.pos).find("bouncing_ball.toml:19:8") != std::string::npos,
               eomc::to_string(r.row.pos));

    // derive() keeps them beside the free equations, and the first-order form carries them.
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.unilateral.size(), 1u);
    BOOST_TEST(eqs.constraints.empty());
    const auto form = eomc::mechanics::first_order_form(model, eqs);
    BOOST_REQUIRE_EQUAL(form.unilateral.size(), 1u);
    BOOST_TEST(form.unilateral.front().row.name == "floor");
    BOOST_TEST(form.constraints.empty());
    // A scleronomic gap: the energy holds between impacts, and the description says it is lost at them.
    const auto energy = std::find_if(eqs.invariants.begin(), eqs.invariants.end(),
                                     [](const auto& i) { return i.name == "energy"; });
    BOOST_REQUIRE(energy != eqs.invariants.end());
    BOOST_TEST(energy->description.find("between impacts only") != std::string::npos, energy->description);
    BOOST_TEST(energy->description.find("Carnot") != std::string::npos, energy->description);
}

BOOST_AUTO_TEST_CASE(pendulum_wall_in_its_angle) {
    const Model model = from_file("pendulum_wall");
    const auto rows = eomc::mechanics::unilateral_rows(model);
    BOOST_REQUIRE_EQUAL(rows.size(), 1u);
    BOOST_TEST(same(rows[0].row.W[0], 1));
    BOOST_TEST(rows[0].row.bias.is_zero());
    BOOST_TEST(model.unilateral[0].restitution_default == 0.6);
}

BOOST_AUTO_TEST_CASE(rod_end_on_the_floor) {
    const Model model = from_string(rod);
    const auto rows = eomc::mechanics::unilateral_rows(model);
    BOOST_REQUIRE_EQUAL(rows.size(), 1u);
    const auto& r = rows[0].row;
    const ex l = symbol_named(model, "l"), theta = symbol_named(model, "theta"),
             theta_dot = symbol_named(model, "theta_dot");
    BOOST_REQUIRE_EQUAL(r.W.size(), 3u);
    BOOST_TEST(same(r.W[0], 0));
    BOOST_TEST(same(r.W[1], 1));
    BOOST_TEST(same(r.W[2], -l * GiNaC::cos(theta)), r.W[2]);
    BOOST_TEST(same(r.bias, l * GiNaC::sin(theta) * GiNaC::pow(theta_dot, 2)), r.bias);
    BOOST_TEST(same(rows[0].restitution, GiNaC::numeric(1, 2)));
}

BOOST_AUTO_TEST_CASE(velocity_row) {
    const Model model = from_string(ratchet);
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.unilateral.size(), 1u);
    const auto& r = eqs.unilateral[0].row;
    BOOST_TEST(!r.holonomic);
    BOOST_TEST(r.position.is_zero());
    BOOST_TEST(same(r.velocity, symbol_named(model, "y_dot")));
    BOOST_TEST(same(r.W[0], 1));
    BOOST_TEST(r.bias.is_zero());
    BOOST_TEST(eqs.unilateral[0].restitution.is_zero());  // the default
    BOOST_TEST(has_energy(eqs));  // homogeneous in the rates and scleronomic
}

BOOST_AUTO_TEST_CASE(rheonomic_gap_drops_energy_and_degenerate_row) {
    std::string moving = rod;
    moving.replace(moving.find("y - l*sin(theta)"), 16, "y - l*sin(theta) + t");
    BOOST_TEST(!has_energy(eomc::mechanics::derive(from_string(moving))));
    BOOST_TEST(has_energy(eomc::mechanics::derive(from_string(rod))));
    std::string degenerate = rod;
    degenerate.replace(degenerate.find("y - l*sin(theta)"), 16, "1 + t");
    try {
        (void)eomc::mechanics::derive(from_string(degenerate));
        BOOST_FAIL("no InputError");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.message().find("'end' is degenerate") != std::string::npos, e.message());
        BOOST_TEST(e.where().line == 22);
    }
}

BOOST_AUTO_TEST_CASE(with_bilateral_rows) {
    // §6.6: a knife-edge sled (a kinematic bilateral row) with a wall x ≤ 1 (a gap 1 − x ≥ 0).
    const Model model = from_string(R"(
[scene]
name = "sled_wall"

[parameters]
m = 1.0
J = 0.2

[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = { initial = 0.0, rate = 0.0 }
phi = { initial = 0.0, rate = 0.0 }

[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2 + J*phi_dot^2/2"
V = "0"

[[constraint]]
name = "blade"
kinematic = "-sin(phi)*x_dot + cos(phi)*y_dot"

[[unilateral]]
name = "wall"
gap = "1 - x"
restitution = "0.5"
)");
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.constraints.size(), 1u);
    BOOST_REQUIRE_EQUAL(eqs.unilateral.size(), 1u);
    BOOST_TEST(same(eqs.unilateral[0].row.W[0], -1));
    const auto form = eomc::mechanics::first_order_form(model, eqs);
    BOOST_TEST(form.constraints.size() == 1u);
    BOOST_TEST(form.unilateral.size() == 1u);
    std::ostringstream text;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    BOOST_TEST(text.str().find("lambda_blade") != std::string::npos);
    BOOST_TEST(text.str().find("lambda_wall") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(derivation_section) {
    const Model model = from_string(rod);
    const auto eqs = eomc::mechanics::derive(model);
    std::ostringstream text, latex, json;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::latex, latex);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::json, json);
    const std::string t = text.str();
    BOOST_TEST_MESSAGE(t);
    // The book's order: the row and its reaction, the equations with λ, Signorini, impact, Newton, Carnot.
    const char* order[] = {"\nUnilateral constraints", "f = ", "admissible virtual displacements", "ideal reaction",
                           "Lagrange's equations with the reactions", "Signorini's conditions",
                           "Impact equations", "Newton's law", "Carnot's theorem", "\nInvariants"};
    std::size_t at = 0;
    for (const char* step : order) {
        const std::size_t next = t.find(step, at);
        BOOST_TEST(next != std::string::npos, "missing or out of order: " << step);
        if (next != std::string::npos) at = next;
    }
    BOOST_TEST(t.find("lambda_end ≥ 0, f_end ≥ 0, lambda_end·f_end = 0") != std::string::npos, t);
    BOOST_TEST(t.find("P_end") != std::string::npos, t);
    BOOST_TEST(t.find("fdot_minus") != std::string::npos, t);

    const std::string l = latex.str();
    BOOST_TEST(l.find("\\subsection*{Unilateral constraints}") != std::string::npos);
    BOOST_TEST(l.find("\\text{end}") != std::string::npos);
    BOOST_TEST(l.find("Signorini") != std::string::npos);
    BOOST_TEST(l.find("\\end{document}") != std::string::npos);

    const std::string j = json.str();
    BOOST_TEST(j.find("\"unilateral\": {") != std::string::npos, j);
    BOOST_TEST(j.find("\"kind\": \"gap\"") != std::string::npos, j);
    BOOST_TEST(j.find("\"carnot\"") != std::string::npos, j);
    // The JSON parses.
    const auto dir = std::filesystem::temp_directory_path() / ("eomc_unilateral_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    { std::ofstream(dir / "d.json") << j; }
    const int rc = std::system(("python3 -m json.tool " + (dir / "d.json").string() + " > /dev/null").c_str());
    BOOST_TEST(rc == 0, j);
    std::filesystem::remove_all(dir);
}

BOOST_AUTO_TEST_CASE(names_escaped) {
    // An underscore in a row's name: \_ inside \text{} in LaTeX; the velocity row prints without impacts.
    std::string toml = ratchet;
    toml.replace(toml.find("\"pawl\""), 6, "\"pawl_1\"");
    const Model model = from_string(toml);
    const auto eqs = eomc::mechanics::derive(model);
    std::ostringstream text, latex, json;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::latex, latex);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::json, json);
    BOOST_TEST(latex.str().find("\\text{pawl\\_1}") != std::string::npos, latex.str());
    BOOST_TEST(latex.str().find("\\lambda_{pawl_1}") == std::string::npos, latex.str());
    BOOST_TEST(text.str().find("a velocity row has no impact") != std::string::npos, text.str());
    BOOST_TEST(text.str().find("Impact equations") == std::string::npos, text.str());
    BOOST_TEST(json.str().find("\"kind\": \"velocity\"") != std::string::npos, json.str());
}

// A moving gap's Carnot balance (the bundled vibrating table, f = y − A sin ωt): the wall's impulse
// does the work −P ∂f/∂t, so the printed T⁺ − T⁻ must equal the kinetic energy change of the exact
// impact, ball speed v⁻ = ḟ⁻ + V against a table moving at V = Aω cos ωt, v⁺ = V − e ḟ⁻. Compared as
// GiNaC expressions read back from the JSON.
BOOST_AUTO_TEST_CASE(moving_gap_carnot_counts_the_wall_work) {
    const Model model = from_file("ball_vibrating_table");
    const auto eqs = eomc::mechanics::derive(model);
    std::ostringstream text, json;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::json, json);
    BOOST_TEST(text.str().find("table moves (∂f/∂t ≠ 0)") != std::string::npos, text.str());
    const std::string j = json.str(), key = "\"carnot\": \"";
    const std::size_t at = j.find(key);
    BOOST_TEST_REQUIRE(at != std::string::npos, j);
    const std::string carnot = j.substr(at + key.size(), j.find('"', at + key.size()) - at - key.size());
    GiNaC::symbol m("m"), e("e"), A("A"), omega("omega"), t("t"), fdot("fdot_minus");
    GiNaC::symtab table{{"m", m}, {"e", e}, {"A", A}, {"omega", omega}, {"t", t}, {"fdot_minus", fdot}};
    GiNaC::parser reader(table, true);
    const ex printed = reader(carnot);
    const ex V = A * omega * GiNaC::cos(omega * t), v_minus = fdot + V, v_plus = V - e * fdot;
    const ex exact = m * (v_plus * v_plus - v_minus * v_minus) / 2;
    BOOST_TEST(GiNaC::normal(GiNaC::expand(printed - exact)).is_zero(), carnot);
}
