// [[unilateral]] and [contact] (Mei, ch. 6): what the scene and the model read, and every refusal
// at its file:line:column — a restitution outside [0, 1], a gap open the wrong way at t = 0, gap
// and velocity in one row, a name already taken by a [[constraint]], the kinds of scene that take
// no unilateral rows, unknown keys and methods with a did-you-mean.
#define BOOST_TEST_MODULE scene_unilateral
#include <boost/test/unit_test.hpp>

#include <string>

#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

using eomc::InputError;

namespace {

// A ball above a floor; `extra` follows the [[unilateral]] table (line 20 on).
std::string ball(const std::string& extra = "", const std::string& restitution = "e", const std::string& y0 = "2.0") {
    return R"([scene]
name = "ball"

[parameters]
m = 1.0
g = 9.81
e = 0.7

[coordinates]
y = { initial = )" + y0 + R"(, rate = 0.0 }

[lagrangian]
T = "m*y_dot^2/2"
V = "m*g*y"

[[unilateral]]
name = "floor"
gap = "y"
restitution = ")" + restitution + "\"\n" + extra;
}

// The error of parsing and modelling `toml` (file "u.toml"); fails when there is none.
InputError error_of(const std::string& toml) {
    try {
        (void)eomc::model::build_model(eomc::scene::parse_scene_string(toml, "u.toml"));
    } catch (const InputError& e) {
        return e;
    }
    BOOST_FAIL("no InputError");
    return InputError({}, "");
}

#define CHECK_ERROR(TOML, WHERE, TEXT)                                                                        \
    do {                                                                                                      \
        const InputError e_ = error_of(TOML);                                                                 \
        BOOST_TEST(eomc::to_string(e_.where()) == (WHERE), eomc::to_string(e_.where()) << ": " << e_.message()); \
        BOOST_TEST(e_.message().find(TEXT) != std::string::npos, e_.message());                              \
    } while (0)

}  // namespace

BOOST_AUTO_TEST_CASE(reads_rows_and_contact) {
    const auto scene = eomc::scene::parse_scene_string(
        ball("\n[[unilateral]]\nname = \"ratchet\"\nvelocity = \"y_dot\"\n\n[contact]\nmethod = \"moreau_jean\"\ntheta = 0.75\n"),
        "u.toml");
    BOOST_REQUIRE_EQUAL(scene.unilateral.size(), 2u);
    BOOST_TEST(scene.unilateral[0].name == "floor");
    BOOST_TEST(scene.unilateral[0].holonomic);
    BOOST_TEST(scene.unilateral[0].expression.text == "y");
    BOOST_TEST(eomc::to_string(scene.unilateral[0].expression.pos) == "u.toml:18:8");
    BOOST_TEST(scene.unilateral[0].restitution.text == "e");
    BOOST_TEST(!scene.unilateral[1].holonomic);
    BOOST_TEST(scene.unilateral[1].restitution.text == "0");  // the default: a plastic row
    BOOST_TEST((scene.contact.method == eomc::runtime::contact::ContactMethod::moreau_jean));
    BOOST_TEST(scene.contact.theta == 0.75);

    const auto model = eomc::model::build_model(scene);
    BOOST_REQUIRE_EQUAL(model.unilateral.size(), 2u);
    BOOST_TEST(model.unilateral[0].restitution_default == 0.7);
    BOOST_TEST(model.unilateral[1].restitution_default == 0.0);
    BOOST_TEST((model.contact_method == eomc::model::ContactMethod::moreau_jean));
    BOOST_TEST(model.theta == 0.75);

    // Without [contact]: event-driven.
    const auto plain = eomc::model::build_model(eomc::scene::parse_scene_string(ball(), "u.toml"));
    BOOST_TEST((plain.contact_method == eomc::model::ContactMethod::event_driven));
    BOOST_TEST((plain.impact_law == eomc::model::ImpactLaw::simultaneous));
    // The multiple-impact law, with its position for the host's diagnostics.
    const auto sequential = eomc::model::build_model(
        eomc::scene::parse_scene_string(ball("[contact]\nimpact_law = \"sequential\"\n"), "u.toml"));
    BOOST_TEST((sequential.impact_law == eomc::model::ImpactLaw::sequential));
    BOOST_TEST(eomc::to_string(sequential.impact_law_pos) == "u.toml:21:14");
    // On the boundary at t = 0 (f = 0) is admissible.
    BOOST_CHECK_NO_THROW(eomc::model::build_model(eomc::scene::parse_scene_string(ball("", "e", "0.0"), "u.toml")));
}

BOOST_AUTO_TEST_CASE(restitution_refusals) {
    CHECK_ERROR(ball("", "1.5"), "u.toml:19:16", "1.5");
    CHECK_ERROR(ball("", "1.5"), "u.toml:19:16", "between 0 (plastic) and 1 (elastic)");
    CHECK_ERROR(ball("", "e - 1"), "u.toml:19:16", "-0.3");
    // Parameters only: a coordinate is refused at its character.
    CHECK_ERROR(ball("", "e*y"), "u.toml:19:18", "y");
}

BOOST_AUTO_TEST_CASE(initial_state_outside) {
    CHECK_ERROR(ball("", "e", "-0.5"), "u.toml:18:8", "violates the unilateral constraint 'floor'");
    CHECK_ERROR(ball("", "e", "-0.5"), "u.toml:18:8", "-0.5");
    // A velocity row: φ(q0, q̇0) < 0.
    CHECK_ERROR(ball("[[unilateral]]\nname = \"ratchet\"\nvelocity = \"y_dot - 1\"\n"), "u.toml:22:13",
                "phi(q0, q0_dot, 0) = -1");
}

BOOST_AUTO_TEST_CASE(row_refusals) {
    CHECK_ERROR(ball("velocity = \"y_dot\"\n"), "u.toml:20:12", "has both 'gap' and 'velocity'");
    CHECK_ERROR(ball("[[unilateral]]\nname = \"lid\"\n"), "u.toml:20:1", "needs 'gap = ");
    CHECK_ERROR(ball("[[constraint]]\nname = \"floor\"\nholonomic = \"y - 2\"\n"), "u.toml:17:8",
                "duplicate unilateral constraint name 'floor' (first declared as a [[constraint]] at line 21)");
    CHECK_ERROR(ball("[[unilateral]]\nname = \"floor\"\ngap = \"y + 1\"\n"), "u.toml:21:8",
                "duplicate unilateral constraint name 'floor' (first declared at line 17)");
    CHECK_ERROR(ball("[[unilateral]]\nname = \"2nd\"\ngap = \"y + 1\"\n"), "u.toml:21:8", "invalid unilateral constraint name");
    CHECK_ERROR(ball("restitutoin = \"e\"\n"), "u.toml:20:1", "did you mean 'restitution'?");
    // Velocity rows are linear in the rates (the bilateral rows' check), and hold one.
    CHECK_ERROR(ball("[[unilateral]]\nname = \"r\"\nvelocity = \"y_dot^2\"\n"), "u.toml:22:13",
                "unilateral velocity constraint 'r' is not linear in the rates");
    CHECK_ERROR(ball("[[unilateral]]\nname = \"r\"\nvelocity = \"y + 1\"\n"), "u.toml:22:13",
                "holds no rate (q_dot); a relation of the coordinates alone is written gap = ");
    // A gap is a function of the coordinates and t.
    CHECK_ERROR(ball("[[unilateral]]\nname = \"r\"\ngap = \"y_dot + 1\"\n"), "u.toml:22:8", "y_dot");
}

BOOST_AUTO_TEST_CASE(contact_refusals) {
    CHECK_ERROR(ball("[contact]\nmethod = \"moreau_jaen\"\n"), "u.toml:21:10", "did you mean 'moreau_jean'?");
    CHECK_ERROR(ball("[contact]\nmethod = \"moreau_jean\"\ntheta = 0.3\n"), "u.toml:22:9", "between 0.5 and 1");
    CHECK_ERROR(ball("[contact]\ntheta = 0.5\n"), "u.toml:21:9", "no meaning with method = \"event_driven\"");
    CHECK_ERROR(ball("[contact]\nmetod = \"moreau_jean\"\n"), "u.toml:21:1", "did you mean 'method'?");
    CHECK_ERROR(ball("[contact]\nimpact_law = \"sequentail\"\n"), "u.toml:21:14", "did you mean 'sequential'?");
    CHECK_ERROR(ball("[contact]\nmethod = \"moreau_jean\"\nimpact_law = \"sequential\"\n"), "u.toml:22:14",
                "needs method = \"event_driven\"");
    std::string no_rows = ball();
    no_rows = no_rows.substr(0, no_rows.find("[[unilateral]]")) + "[contact]\nmethod = \"event_driven\"\n";
    CHECK_ERROR(no_rows, "u.toml:16:1", "declares no [[unilateral]] row");
}

BOOST_AUTO_TEST_CASE(scenes_without_rows) {
    CHECK_ERROR(R"([scene]
name = "top"

[parameters]
P = 1.0

[rigid_body]
inertia = ["1", "1", "0.5"]
center = ["0", "0", "1"]
weight = "P"
initial = { omega = [0.0, 0.0, 1.0], vertical = [0.0, 0.0, 1.0] }

[[unilateral]]
name = "floor"
gap = "gamma3"
)",
                "u.toml:13:1", "[[unilateral]] is not supported in a [rigid_body] scene");
    CHECK_ERROR(R"([scene]
name = "leo"

[parameters]
mu = 398600.4418
Re = 6378.137

[orbit]
central_body = { mu = "mu", radius = "Re" }
elements = { a = 7000.0, e = 0.01, i = 10.0 }

[[unilateral]]
name = "above"
gap = "z"
)",
                "u.toml:12:1", "[[unilateral]] is not supported in an [orbit] scene");
    CHECK_ERROR(R"([scene]
name = "given"

[coordinates]
y = { initial = 1.0 }

[newtonian]
y_ddot = "-1"

[[unilateral]]
name = "floor"
gap = "y"
)",
                "u.toml:10:1", "[[unilateral]] is not supported in a [newtonian] scene");
    CHECK_ERROR(ball("", "e") + "\n[formulation]\nkind = \"hamiltonian\"\n", "u.toml:16:1",
                "not supported with [formulation] kind = \"hamiltonian\"");
    CHECK_ERROR(R"([scene]
name = "free_box"

[parameters]
m = 1.0
M = 2.0

[coordinates]
x = { initial = 1.0 }

[carrier]
motion = "free"
angular_velocity = ["0", "0", "0"]
pole_velocity = ["v1", "0", "0"]
mass = "M"
inertia = ["1", "1", "1"]

[[body]]
name = "ball"
mass = "m"
position = ["x", "0", "0"]

[[unilateral]]
name = "wall"
gap = "x"
)",
                "u.toml:23:1", "not supported with a free carrier");
}
