// The scene parser: a full scene read field by field, each error kind with its exact
// position, and the examples in docs/scene-format.md.
#define BOOST_TEST_MODULE scene_parser
#include <boost/test/unit_test.hpp>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <toml++/toml.h>

#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

using eomc::InputError;
using eomc::scene::parse_scene_file;
using eomc::scene::parse_scene_string;
using eomc::scene::Scene;

namespace {

// The format's reference example, less its [lagrangian] (the alternative to [[body]]).
const char* const disk_tube_ball = R"([scene]
name = "disk_tube_ball"            # [a-z][a-z0-9_]*; required
summary = "Disc spinning about y', smooth tube along x' through o, ball inside"   # optional

[parameters]                       # constants with defaults (numbers; integers accepted)
M = 2.0
m = 0.5
r = 0.3
Omega = 3.0

[coordinates]                      # generalized coordinates; each an inline table, both keys optional (default 0)
q = { initial = 0.1, rate = 0.0 }

[carrier]                          # optional; absent = bodies move in an inertial frame
motion = "prescribed"              # "prescribed" | "free"  (free is refused later by the model, not here)
angular_velocity = ["0", "Omega", "0"]   # 3 expressions (strings; a number is accepted and kept as its text)
pole_velocity = ["0", "0", "0"]          # 3 expressions; each vector optional, default ["0","0","0"]

[[body]]                           # carried particles, array of tables, at least one unless [lagrangian] is given
name = "ball"                      # identifier, unique
mass = "m"                         # expression (string or number); a literal number <= 0 is an error here
position = ["q", "0", "0"]         # 3 expressions, carrier axes

[forces]                           # all optional
potential = "0"                    # V(q, t), expression
generalized = { q = "0" }          # Q_s per coordinate name (names are checked later by the model)

[effects]                          # only allowed when there is a [carrier]; default: all kept
keep = ["relative", "translation", "euler", "centrifugal", "coriolis"]

[simulate]                         # all optional
t_end = 2.0                        # > 0
integrator = "dopri5"              # "rk4" | "dopri5"
rtol = 1e-10                       # > 0
atol = 1e-12                       # > 0
step = 1e-3                        # > 0, for rk4
)";

void check_pos(const eomc::SourcePos& p, int line, int column, const std::string& file = "t.toml") {
    BOOST_TEST(p.file == file);
    BOOST_TEST(p.line == line);
    BOOST_TEST(p.column == column);
}

// Parsing `text` must throw an InputError at (line, column) whose message contains `fragment`.
void expect_error(const std::string& text, int line, int column, const std::string& fragment) {
    try {
        parse_scene_string(text, "t.toml");
    } catch (const InputError& e) {
        BOOST_TEST_INFO("message: " << e.what());
        check_pos(e.where(), line, column);
        BOOST_TEST(e.message().find(fragment) != std::string::npos,
                   "message '" << e.message() << "' does not contain '" << fragment << "'");
        return;
    }
    BOOST_ERROR("no InputError for a scene that should fail with '" << fragment << "'");
}

}  // namespace

// --- a full scene ------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(reference_example_every_field) {
    const Scene s = parse_scene_string(disk_tube_ball, "t.toml");
    BOOST_TEST(s.path == "");
    BOOST_TEST(s.name == "disk_tube_ball");
    BOOST_TEST(s.summary == "Disc spinning about y', smooth tube along x' through o, ball inside");
    check_pos(s.name_pos, 2, 8);

    BOOST_TEST_REQUIRE(s.parameters.size() == 4u);  // file order, not toml++'s sorted order
    const char* names[] = {"M", "m", "r", "Omega"};
    const double values[] = {2.0, 0.5, 0.3, 3.0};
    for (std::size_t i = 0; i < 4; ++i) {
        BOOST_TEST(s.parameters[i].name == names[i]);
        BOOST_TEST(s.parameters[i].value == values[i]);
        check_pos(s.parameters[i].pos, 6 + static_cast<int>(i), 1);
    }

    BOOST_TEST_REQUIRE(s.coordinates.size() == 1u);
    BOOST_TEST(s.coordinates[0].name == "q");
    BOOST_TEST(s.coordinates[0].initial == 0.1);
    BOOST_TEST(s.coordinates[0].rate == 0.0);
    check_pos(s.coordinates[0].pos, 12, 1);

    BOOST_TEST_REQUIRE(s.carrier.has_value());
    BOOST_TEST(s.carrier->motion == "prescribed");
    check_pos(s.carrier->motion_pos, 15, 10);
    check_pos(s.carrier->pos, 14, 1);
    BOOST_TEST(s.carrier->angular_velocity[0].text == "0");
    BOOST_TEST(s.carrier->angular_velocity[1].text == "Omega");
    BOOST_TEST(s.carrier->angular_velocity[2].text == "0");
    check_pos(s.carrier->angular_velocity[0].pos, 16, 22);
    check_pos(s.carrier->angular_velocity[1].pos, 16, 27);
    check_pos(s.carrier->angular_velocity[2].pos, 16, 36);
    for (const auto& e : s.carrier->pole_velocity) BOOST_TEST(e.text == "0");
    check_pos(s.carrier->pole_velocity[2].pos, 17, 29);

    BOOST_TEST_REQUIRE(s.bodies.size() == 1u);
    BOOST_TEST(s.bodies[0].name == "ball");
    BOOST_TEST(s.bodies[0].mass.text == "m");
    check_pos(s.bodies[0].mass.pos, 21, 9);
    check_pos(s.bodies[0].pos, 19, 1);
    BOOST_TEST(s.bodies[0].position[0].text == "q");
    BOOST_TEST(s.bodies[0].position[1].text == "0");
    BOOST_TEST(s.bodies[0].position[2].text == "0");
    check_pos(s.bodies[0].position[0].pos, 22, 14);

    BOOST_TEST(!s.lagrangian.has_value());

    BOOST_TEST_REQUIRE(s.forces.potential.has_value());
    BOOST_TEST(s.forces.potential->text == "0");
    check_pos(s.forces.potential->pos, 25, 14);
    BOOST_TEST_REQUIRE(s.forces.generalized.size() == 1u);
    BOOST_TEST(s.forces.generalized[0].coordinate == "q");
    BOOST_TEST(s.forces.generalized[0].value.text == "0");
    check_pos(s.forces.generalized[0].pos, 26, 17);
    check_pos(s.forces.generalized[0].value.pos, 26, 22);

    BOOST_TEST(s.effects.given);
    const std::vector<std::string> keep{"relative", "translation", "euler", "centrifugal", "coriolis"};
    BOOST_TEST(s.effects.keep == keep, boost::test_tools::per_element());
    BOOST_TEST_REQUIRE(s.effects.keep_pos.size() == 5u);
    check_pos(s.effects.keep_pos[0], 29, 9);
    check_pos(s.effects.keep_pos[1], 29, 21);

    BOOST_TEST(s.simulate.t_end == 2.0);
    BOOST_TEST(s.simulate.integrator == "dopri5");
    check_pos(s.simulate.integrator_pos, 33, 14);
    BOOST_TEST(s.simulate.rtol == 1e-10);
    BOOST_TEST(s.simulate.atol == 1e-12);
    BOOST_TEST(s.simulate.step == 1e-3);
}

BOOST_AUTO_TEST_CASE(parse_file_reports_its_path) {
    const auto dir = std::filesystem::temp_directory_path() / "eomc_test_scene_parser";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "disk_tube_ball.toml").string();
    {
        std::ofstream out(path, std::ios::binary);
        out << disk_tube_ball;
    }
    const Scene s = parse_scene_file(path);
    BOOST_TEST(s.path == path);
    BOOST_TEST(s.name == "disk_tube_ball");
    check_pos(s.bodies[0].mass.pos, 21, 9, path);

    {
        std::ofstream out(path, std::ios::binary);
        out << "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n"
               "[effects]\nkep = []\n";
    }
    try {
        parse_scene_file(path);
        BOOST_ERROR("no InputError");
    } catch (const InputError& e) {
        check_pos(e.where(), 10, 1, path);
        BOOST_TEST(std::string(e.what()) == path + ":10:1: error: unknown key 'kep' in [effects]; did you mean 'keep'?");
    }
    std::filesystem::remove_all(dir);
}

BOOST_AUTO_TEST_CASE(missing_file) {
    const std::string path = "/nonexistent/eomc/scene.toml";
    try {
        parse_scene_file(path);
        BOOST_ERROR("no InputError");
    } catch (const InputError& e) {
        BOOST_TEST(e.where().file == path);
        BOOST_TEST(!e.where().known());
        BOOST_TEST(e.message().find(path) != std::string::npos);
        BOOST_TEST(e.message().find("no such file or directory") != std::string::npos, e.message());
    }
}

BOOST_AUTO_TEST_CASE(directory_is_not_a_scene) {
    const std::string path = std::filesystem::temp_directory_path().string();
    try {
        parse_scene_file(path);
        BOOST_ERROR("no InputError");
    } catch (const InputError& e) {
        BOOST_TEST(e.message().find("is a directory") != std::string::npos, e.message());
    }
}

BOOST_AUTO_TEST_CASE(lagrangian_without_carrier) {
    const Scene s = parse_scene_string(R"([scene]
name = "falling"
[parameters]
m = 1
g = 9.81
[coordinates]
q = { initial = 2 }
[lagrangian]
T = "m*q_dot^2/2"
V = "m*g*q"
)",
                                       "t.toml");
    BOOST_TEST(!s.carrier.has_value());
    BOOST_TEST(s.bodies.empty());
    BOOST_TEST_REQUIRE(s.lagrangian.has_value());
    BOOST_TEST(s.lagrangian->kinetic.text == "m*q_dot^2/2");
    check_pos(s.lagrangian->kinetic.pos, 9, 6);
    BOOST_TEST(s.lagrangian->potential.text == "m*g*q");
    check_pos(s.lagrangian->potential.pos, 10, 6);
    check_pos(s.lagrangian->pos, 8, 1);
    BOOST_TEST(s.parameters[0].value == 1.0);  // an integer parameter
    BOOST_TEST(s.coordinates[0].initial == 2.0);
}

BOOST_AUTO_TEST_CASE(lagrangian_potential_defaults_to_zero) {
    const Scene s = parse_scene_string("[scene]\nname = \"free\"\n[coordinates]\nx = {}\n[lagrangian]\nT = \"x_dot^2/2\"\n",
                                       "t.toml");
    BOOST_TEST_REQUIRE(s.lagrangian.has_value());
    BOOST_TEST(s.lagrangian->potential.text == "0");
}

// [kernel] jacobian: off unless the scene says so.
BOOST_AUTO_TEST_CASE(kernel_jacobian_key) {
    const std::string free = "[scene]\nname = \"free\"\n[coordinates]\nx = {}\n[lagrangian]\nT = \"x_dot^2/2\"\n";
    BOOST_TEST(!parse_scene_string(free, "t.toml").kernel_jacobian);
    BOOST_TEST(parse_scene_string(free + "[kernel]\njacobian = true\n", "t.toml").kernel_jacobian);
    BOOST_TEST(!parse_scene_string(free + "[kernel]\njacobian = false\n", "t.toml").kernel_jacobian);
}

BOOST_AUTO_TEST_CASE(bodies_without_carrier) {
    const Scene s = parse_scene_string(R"([scene]
name = "two_balls"
[coordinates]
x = {}
y = { rate = -1 }
[[body]]
name = "a"
mass = "m1"
position = ["x", "0", "0"]
[[body]]
name = "b"
mass = "m2"
position = ["0", "y", "0"]
)",
                                       "t.toml");
    BOOST_TEST(!s.carrier.has_value());
    BOOST_TEST_REQUIRE(s.bodies.size() == 2u);
    BOOST_TEST(s.bodies[0].name == "a");
    BOOST_TEST(s.bodies[1].name == "b");
    check_pos(s.bodies[1].pos, 10, 1);
    BOOST_TEST(s.bodies[1].position[1].text == "y");
    BOOST_TEST(s.coordinates[1].rate == -1.0);
    BOOST_TEST(!s.effects.given);
}

BOOST_AUTO_TEST_CASE(numbers_accepted_as_expressions) {
    const Scene s = parse_scene_string(R"([scene]
name = "numbers"
[coordinates]
q = {}
[carrier]
angular_velocity = [0, 2.5, -1]
pole_velocity = [1_000, +0.5, 1E-3]
[[body]]
name = "b"
mass = 2
position = ["q", 0x10, 0.0]
[forces]
potential = 0
generalized = { q = -3.25 }
)",
                                       "t.toml");
    const auto& w = s.carrier->angular_velocity;
    BOOST_TEST(w[0].text == "0");
    BOOST_TEST(w[1].text == "2.5");
    BOOST_TEST(w[2].text == "-1");
    check_pos(w[0].pos, 6, 21);
    check_pos(w[1].pos, 6, 24);
    check_pos(w[2].pos, 6, 29);
    const auto& v = s.carrier->pole_velocity;
    BOOST_TEST(v[0].text == "1000");
    BOOST_TEST(v[1].text == "0.5");
    BOOST_TEST(v[2].text == "1e-3");
    BOOST_TEST(s.bodies[0].mass.text == "2");
    check_pos(s.bodies[0].mass.pos, 10, 8);
    BOOST_TEST(s.bodies[0].position[1].text == "16");
    BOOST_TEST(s.bodies[0].position[2].text == "0.0");
    BOOST_TEST(s.forces.potential->text == "0");
    BOOST_TEST(s.forces.generalized[0].value.text == "-3.25");
}

BOOST_AUTO_TEST_CASE(defaults_applied) {
    const Scene s = parse_scene_string(R"([scene]
name = "defaults"
[coordinates]
q = {}
[carrier]
[[body]]
name = "b"
mass = "m"
position = ["q", "0", "0"]
)",
                                       "t.toml");
    BOOST_TEST(s.summary == "");
    BOOST_TEST(s.parameters.empty());
    BOOST_TEST(s.coordinates[0].initial == 0.0);
    BOOST_TEST(s.coordinates[0].rate == 0.0);
    BOOST_TEST_REQUIRE(s.carrier.has_value());
    BOOST_TEST(s.carrier->motion == "prescribed");
    for (const auto& e : s.carrier->angular_velocity) BOOST_TEST(e.text == "0");
    for (const auto& e : s.carrier->pole_velocity) BOOST_TEST(e.text == "0");
    BOOST_TEST(!s.lagrangian.has_value());
    BOOST_TEST(!s.forces.potential.has_value());
    BOOST_TEST(s.forces.generalized.empty());
    BOOST_TEST(!s.effects.given);  // keep all
    BOOST_TEST(s.effects.keep.empty());
    BOOST_TEST(s.simulate.t_end == 10.0);
    BOOST_TEST(s.simulate.integrator == "dopri5");
    BOOST_TEST(s.simulate.rtol == 1e-10);
    BOOST_TEST(s.simulate.atol == 1e-12);
    BOOST_TEST(s.simulate.step == 1e-3);
}

BOOST_AUTO_TEST_CASE(expression_positions_inside_other_string_kinds) {
    const Scene s = parse_scene_string("[scene]\nname = \"k\"\n[coordinates]\nq = {}\n[lagrangian]\n"
                                       "T = 'q_dot^2'\n"
                                       "V = \"\"\"\n  q^2\"\"\"\n",
                                       "t.toml");
    check_pos(s.lagrangian->kinetic.pos, 6, 6);
    BOOST_TEST(s.lagrangian->potential.text == "  q^2");
    check_pos(s.lagrangian->potential.pos, 8, 1);
    BOOST_TEST(s.lagrangian->potential.pos.shifted(2).column == 3);  // the 'q'
}

BOOST_AUTO_TEST_CASE(free_carrier_needs_its_mass_and_takes_inertia_as_moments_or_matrix) {
    const std::string head = "[scene]\nname = \"f\"\n[coordinates]\nq = {}\n[carrier]\nmotion = \"free\"\n";
    const std::string body = "[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n";
    expect_error(head + body, 5, 1, "missing required key 'mass'");
    const Scene s = parse_scene_string(head + "mass = \"2\"\ninertia = [[1, 0, 0], [0, 2, 0], [0, 0, 3]]\n"
                                              "angular_velocity = [\"0\", \"w\", \"0\"]\n[carrier.initial]\nw = 1.5\n" + body,
                                       "t.toml");
    BOOST_TEST(s.carrier->motion == "free");
    check_pos(s.carrier->motion_pos, 6, 10);
    BOOST_TEST(s.carrier->inertia.size() == 9u);
    BOOST_TEST(s.carrier->inertia[8].text == "3");
    BOOST_REQUIRE(s.carrier->initial.size() == 1u);
    BOOST_TEST(s.carrier->initial[0].value == 1.5);
    // A prescribed carrier may give its mass (for the forces that hold it), never initial quasi-velocities.
    const Scene prescribed =
        parse_scene_string("[scene]\nname = \"f\"\n[coordinates]\nq = {}\n[carrier]\nmass = \"2\"\n" + body, "t.toml");
    BOOST_REQUIRE(prescribed.carrier->mass.has_value());
    BOOST_TEST(prescribed.carrier->mass->text == "2");
    BOOST_TEST(prescribed.carrier->inertia.empty());
    expect_error("[scene]\nname = \"f\"\n[coordinates]\nq = {}\n[carrier]\n[carrier.initial]\nw = 1\n" + body, 6, 1,
                 "only for a free carrier");
}

BOOST_AUTO_TEST_CASE(rk4_with_integer_settings) {
    const Scene s = parse_scene_string("[scene]\nname = \"r\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n"
                                       "[simulate]\nt_end = 5\nintegrator = \"rk4\"\nstep = 1\n",
                                       "t.toml");
    BOOST_TEST(s.simulate.t_end == 5.0);
    BOOST_TEST(s.simulate.integrator == "rk4");
    check_pos(s.simulate.integrator_pos, 9, 14);
    BOOST_TEST(s.simulate.step == 1.0);
}

BOOST_AUTO_TEST_CASE(events_in_both_forms_and_compensated) {
    const Scene s = parse_scene_string("[scene]\nname = \"e\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n"
                                       "[simulate]\nintegrator = \"kahanli8\"\ncompensated = false\n"
                                       "[events]\nzero = \"q\"\n"
                                       "turn = { when = \"q_dot\", direction = \"up\", terminal = true }\n",
                                       "t.toml");
    BOOST_TEST(s.simulate.integrator == "kahanli8");
    BOOST_REQUIRE(s.simulate.compensated.has_value());
    BOOST_TEST(!*s.simulate.compensated);
    BOOST_REQUIRE(s.events.size() == 2u);  // file order
    BOOST_TEST(s.events[0].name == "zero");
    BOOST_TEST(s.events[0].when.text == "q");
    check_pos(s.events[0].when.pos, 11, 9);
    BOOST_TEST(s.events[0].direction == "both");
    BOOST_TEST(!s.events[0].terminal);
    BOOST_TEST(s.events[1].name == "turn");
    BOOST_TEST(s.events[1].when.text == "q_dot");
    check_pos(s.events[1].when.pos, 12, 18);
    BOOST_TEST(s.events[1].direction == "up");
    BOOST_TEST(s.events[1].terminal);
    // Without [simulate] compensated the integrator's default applies (decided by simulate).
    BOOST_TEST(!parse_scene_string("[scene]\nname = \"e\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n")
                    .simulate.compensated.has_value());
    BOOST_TEST(eomc::runtime::find_integrator("gl6")->compensated_by_default);
    BOOST_TEST(eomc::runtime::find_integrator("verlet")->compensated_by_default);
    BOOST_TEST(!eomc::runtime::find_integrator("dop853")->compensated_by_default);
    BOOST_TEST(eomc::runtime::find_integrator("yoshida6")->fixed_step());
}

// --- errors, one kind at a time ---------------------------------------------------------

BOOST_AUTO_TEST_CASE(event_errors) {
    const std::string head = "[scene]\nname = \"e\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n[events]\n";
    expect_error(head + "z = { direction = \"up\" }\n", 8, 5, "missing required key 'when'");
    expect_error(head + "z = { when = \"q\", direction = \"sideways\" }\n", 8, 31, "unknown direction 'sideways'");
    expect_error(head + "z = { when = \"q\", terminal = \"yes\" }\n", 8, 30, "expected true or false");
    expect_error(head + "z = { when = \"q\", wehn = \"q\" }\n", 8, 19, "unknown key 'wehn'");
    expect_error(head + "\"a b\" = \"q\"\n", 8, 1, "invalid event name 'a b'");
    expect_error(head + "z = [\"q\"]\n", 8, 5, "expected an expression");
    expect_error("[scene]\nname = \"e\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n"
                 "[simulate]\ncompensated = 1\n",
                 8, 15, "'simulate.compensated': expected true or false");
    expect_error("[scene]\nname = \"e\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n"
                 "[simulate]\nintegrator = \"kahanli9\"\n",
                 8, 14, "did you mean 'kahanli8'?");
}

BOOST_AUTO_TEST_CASE(error_message_format) {
    try {
        parse_scene_string("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q\"\n[simulate]\nintegratr = 1\n",
                           "scenes/x.toml");
        BOOST_ERROR("no InputError");
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()) ==
                   "scenes/x.toml:8:1: error: unknown key 'integratr' in [simulate]; did you mean 'integrator'?");
    }
}

BOOST_AUTO_TEST_CASE(toml_syntax_error) {
    expect_error("[scene]\nname = \n", 2, 8, "invalid TOML");
    expect_error("[scene]\nname = \"x\"\nname = \"y\"\n", 3, 8, "cannot redefine existing string 'name'");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = { initial = 0.1,\n", 4, 21, "invalid TOML in inline table");
}

BOOST_AUTO_TEST_CASE(unknown_key_top_level) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[simulation]\nt_end = 1\n", 5, 2,
                 "unknown key 'simulation' at the top level; did you mean 'simulate'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[boddy]]\nname = \"b\"\n", 5, 3,
                 "unknown key 'boddy' at the top level; did you mean 'body'?");
}

BOOST_AUTO_TEST_CASE(unknown_key_in_section) {
    expect_error("[scene]\nname = \"x\"\n  titel = \"y\"\n", 3, 3, "unknown key 'titel' in [scene]; expected one of: name, summary");
    expect_error("[scene]\nname = \"x\"\nsumary = \"y\"\n", 3, 1, "unknown key 'sumary' in [scene]; did you mean 'summary'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = { inital = 0.1 }\n", 4, 7,
                 "unknown key 'inital' in 'coordinates.q'; did you mean 'initial'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\nangular_velocty = [0, 0, 1]\n", 6, 1,
                 "unknown key 'angular_velocty' in [carrier]; did you mean 'angular_velocity'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmasss = 1\n", 7, 1,
                 "unknown key 'masss' in [[body]]; did you mean 'mass'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q\"\nU = \"q\"\n", 7, 1,
                 "unknown key 'U' in [lagrangian]");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q\"\n[forces]\npotentail = \"q\"\n", 8, 1,
                 "unknown key 'potentail' in [forces]; did you mean 'potential'?");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\n[[body]]\nname = \"b\"\nmass = 1\n"
                 "position = [\"q\", 0, 0]\n[effects]\ncoriollis = true\n",
                 11, 1, "unknown key 'coriollis' in [effects]; expected one of: keep");
}

BOOST_AUTO_TEST_CASE(missing_required_keys) {
    expect_error("[coordinates]\nq = {}\n", 1, 1, "missing required table [scene]");
    expect_error("[parameters]\nm = 1\n\n[scene]\nsummary = \"no name\"\n", 4, 1, "missing required key 'name' in [scene]");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nposition = [0, 0, 0]\n", 5, 1,
                 "missing required key 'mass' in [[body]]");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmass = 1\n", 5, 1,
                 "missing required key 'position' in [[body]]");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nmass = 1\n", 5, 1,
                 "missing required key 'name' in [[body]]");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nV = \"q\"\n", 5, 1,
                 "missing required key 'T' in [lagrangian]");
}

BOOST_AUTO_TEST_CASE(wrong_types) {
    expect_error("[scene]\nname = 3\n", 2, 8, "'scene.name': expected a string, got an integer");
    expect_error("scene = \"x\"\n", 1, 9, "'scene': expected a table, got a string");
    expect_error("[scene]\nname = \"x\"\n[parameters]\nm = \"2.0\"\n", 4, 5, "'parameters.m': expected a number, got a string");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = 0.1\n", 4, 5, "'coordinates.q': expected a table, got a float");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = { rate = true }\n", 4, 14,
                 "'coordinates.q.rate': expected a number, got a boolean");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmass = true\n", 7, 8,
                 "'body[0].mass': expected an expression (a string or a number), got a boolean");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[body]\nname = \"b\"\n", 5, 1,
                 "'body': expected an array of tables ([[body]]), got a table");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\nangular_velocity = \"0, 0, w\"\n", 6, 20,
                 "'carrier.angular_velocity': expected an array of 3 expressions, got a string");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q\"\n[simulate]\nt_end = \"2\"\n", 8, 9,
                 "'simulate.t_end': expected a number, got a string");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\n[[body]]\nname = \"b\"\nmass = 1\n"
                 "position = [\"q\", 0, 0]\n[effects]\nkeep = [\"euler\", 2]\n",
                 11, 18, "'effects.keep[1]': expected a string, got an integer");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q\"\n[forces]\ngeneralized = [\"0\"]\n", 8,
                 15, "'forces.generalized': expected a table, got an array");
}

BOOST_AUTO_TEST_CASE(vector_length) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", \"0\"]\n", 8,
                 12, "'body[0].position': expected 3 components, got 2");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\npole_velocity = [0, 0, 0, 0]\n", 6, 17,
                 "'carrier.pole_velocity': expected 3 components, got 4");
}

BOOST_AUTO_TEST_CASE(invalid_names) {
    expect_error("[scene]\nname = \"Disk-Tube\"\n", 2, 8, "invalid scene name 'Disk-Tube'");
    expect_error("[scene]\nname = \"2disk\"\n", 2, 8, "invalid scene name '2disk'");
    expect_error("[scene]\nname = \"x\"\n[parameters]\n\"2m\" = 1\n", 4, 1, "invalid parameter name '2m'");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\n_q = {}\n", 4, 1, "invalid coordinate name '_q'");
    // Letters are ASCII whatever the locale: a quoted TOML key may hold any UTF-8.
    expect_error("[scene]\nname = \"x\"\n[coordinates]\n\"θ\" = {}\n", 4, 1, "invalid coordinate name 'θ'");
    expect_error("[scene]\nname = \"x\"\n[parameters]\n\"m\u00e9\" = 1\n", 4, 1, "invalid parameter name 'mé'");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"the ball\"\n", 6, 8,
                 "invalid body name 'the ball'");
}

BOOST_AUTO_TEST_CASE(reserved_names) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nt = {}\n", 4, 1, "'t' is reserved for the time");
    expect_error("[scene]\nname = \"x\"\n[parameters]\nPi = 3.14\n", 4, 1, "'Pi' is reserved");
    for (const char* f : {"sin", "cos", "tan", "exp", "log", "sqrt", "asin", "acos", "atan"})
        expect_error(std::string("[scene]\nname = \"x\"\n[parameters]\n  ") + f + " = 1\n", 4, 3,
                     std::string("'") + f + "' is reserved for a built-in function and cannot name a parameter");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq_dot = {}\n", 4, 1,
                 "coordinate name 'q_dot' ends in '_dot', which is reserved");
    expect_error("[scene]\nname = \"x\"\n[parameters]\nx_ddot = 1\n", 4, 1,
                 "parameter name 'x_ddot' ends in '_ddot', which is reserved");
}

BOOST_AUTO_TEST_CASE(parameter_and_coordinate_share_a_name) {
    expect_error("[scene]\nname = \"x\"\n[parameters]\nq = 1\n[coordinates]\nq = {}\n", 6, 1,
                 "coordinate 'q' has the same name as the parameter declared at line 4");
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[parameters]\nq = 1\n", 6, 1,
                 "parameter 'q' has the same name as the coordinate declared at line 4");
}

BOOST_AUTO_TEST_CASE(duplicate_body_names) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n"
                 "[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n"
                 "[[body]]\nname = \"b\"\nmass = 1\nposition = [0, \"q\", 0]\n",
                 10, 8, "duplicate body name 'b' (first declared at line 6)");
}

BOOST_AUTO_TEST_CASE(unknown_effect) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\n[[body]]\nname = \"b\"\nmass = 1\n"
                             "position = [\"q\", 0, 0]\n[effects]\n";
    expect_error(head + "keep = [\"euler\", \"coriollis\"]\n", 11, 18,
                 "unknown effect 'coriollis' in effects.keep; did you mean 'coriolis'?");
    expect_error(head + "keep = [\"gravity\"]\n", 11, 9, "unknown effect 'gravity' in effects.keep; expected one of:");
    expect_error(head + "keep = \"euler\"\n", 11, 8, "'effects.keep': expected an array of effect names, got a string");
}

BOOST_AUTO_TEST_CASE(duplicate_effect) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\n[[body]]\nname = \"b\"\nmass = 1\n"
                 "position = [\"q\", 0, 0]\n[effects]\nkeep = [\"euler\", \"coriolis\", \"euler\"]\n",
                 11, 30, "effect 'euler' appears twice in effects.keep (first at line 11, column 9)");
}

BOOST_AUTO_TEST_CASE(lagrangian_conflicts) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n";
    expect_error(head + "[lagrangian]\nT = \"q_dot^2\"\n[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n", 7, 1,
                 "[[body]] cannot be combined with [lagrangian] (line 5)");
    expect_error(head + "[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n[lagrangian]\nT = \"q_dot^2\"\n", 9, 1,
                 "[lagrangian] cannot be combined with [[body]] (line 5)");
    expect_error(head + "[lagrangian]\nT = \"q_dot^2\"\n[effects]\nkeep = [\"euler\"]\n", 7, 1,
                 "[effects] cannot be combined with [lagrangian] (line 5)");
    expect_error(head + "[carrier]\nangular_velocity = [0, 0, 1]\n[lagrangian]\nT = \"q_dot^2\"\n", 7, 1,
                 "[lagrangian] cannot be combined with [carrier] (line 5)");
}

BOOST_AUTO_TEST_CASE(effects_without_carrier) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", 0, 0]\n"
                 "[effects]\nkeep = [\"relative\"]\n",
                 9, 1, "[effects] requires a [carrier]");
}

BOOST_AUTO_TEST_CASE(neither_bodies_nor_lagrangian) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\n", 1, 1,
                 "the scene has neither [[body]] nor [lagrangian]");
    expect_error("body = []\n[scene]\nname = \"x\"\n[coordinates]\nq = {}\n", 1, 8, "'body': expected at least one [[body]]");
}

BOOST_AUTO_TEST_CASE(no_coordinates) {
    expect_error("[scene]\nname = \"x\"\n[lagrangian]\nT = \"1\"\n", 1, 1, "missing required table [coordinates]");
    expect_error("[scene]\nname = \"x\"\n\n[coordinates]\n[lagrangian]\nT = \"1\"\n", 4, 1, "[coordinates] declares no coordinate");
}

BOOST_AUTO_TEST_CASE(empty_expression) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n";
    expect_error(head + "[lagrangian]\nT = \"\"\n", 6, 5, "'lagrangian.T': empty expression");
    expect_error(head + "[[body]]\nname = \"b\"\nmass = \"m\"\nposition = [\"q\", \"  \", \"0\"]\n", 8, 18,
                 "'body[0].position[1]': empty expression");
    expect_error(head + "[lagrangian]\nT = \"q_dot^2\"\n[forces]\ngeneralized = { q = '' }\n", 8, 21,
                 "'forces.generalized.q': empty expression");
}

BOOST_AUTO_TEST_CASE(non_positive_mass_literal) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[[body]]\nname = \"b\"\n";
    expect_error(head + "mass = 0\nposition = [\"q\", 0, 0]\n", 7, 8, "'body[0].mass': a mass must be positive, got 0");
    expect_error(head + "mass = \"-1.5\"\nposition = [\"q\", 0, 0]\n", 7, 9, "a mass must be positive, got -1.5");
    // A symbolic mass is checked later, by the model.
    BOOST_CHECK_NO_THROW(parse_scene_string(head + "mass = \"-m\"\nposition = [\"q\", 0, 0]\n", "t.toml"));
}

BOOST_AUTO_TEST_CASE(non_positive_simulation_settings) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n[simulate]\n";
    expect_error(head + "t_end = 0\n", 8, 9, "'simulate.t_end' must be positive, got 0");
    expect_error(head + "rtol = -1e-6\n", 8, 8, "'simulate.rtol' must be positive, got -1e-6");
    expect_error(head + "atol = 0.0\n", 8, 8, "'simulate.atol' must be positive, got 0.0");
    expect_error(head + "step = -1\n", 8, 8, "'simulate.step' must be positive, got -1");
    expect_error(head + "t_end = nan\n", 8, 9, "'simulate.t_end': expected a finite number, got nan");
}

BOOST_AUTO_TEST_CASE(unknown_integrator) {
    const std::string head = "[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[lagrangian]\nT = \"q_dot^2\"\n[simulate]\n";
    expect_error(head + "integrator = \"dopri\"\n", 8, 14, "unknown integrator 'dopri'; did you mean 'dopri5'?");
    expect_error(head + "integrator = \"euler\"\n", 8, 14, "unknown integrator 'euler'; expected one of rk4, dopri5, dop853, radau5, gl4, gl6, gl8");
}

BOOST_AUTO_TEST_CASE(unknown_carrier_motion) {
    expect_error("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n[carrier]\nmotion = \"prescibed\"\n", 6, 10,
                 "unknown carrier motion 'prescibed'; did you mean 'prescribed'?");
}

// --- the documentation ------------------------------------------------------------------

// Every ```toml block in docs/scene-format.md is valid TOML, and every block with a
// [scene] table is a complete scene that parses.
BOOST_AUTO_TEST_CASE(documentation_examples_parse) {
    const std::string path = std::string(EOMC_SOURCE_DIR) + "/docs/scene-format.md";
    std::ifstream in(path);
    BOOST_TEST_REQUIRE(static_cast<bool>(in), "cannot open " << path);
    std::string line, block;
    bool inside = false;
    int start = 0, number = 0, blocks = 0, scenes = 0;
    while (std::getline(in, line)) {
        ++number;
        if (!inside && line == "```toml") {
            inside = true;
            block.clear();
            start = number + 1;
        } else if (inside && line == "```") {
            inside = false;
            ++blocks;
            BOOST_TEST_CONTEXT("the toml block at " << path << ":" << start) {
                BOOST_CHECK_NO_THROW(toml::parse(block));
                if (block.find("[scene]") != std::string::npos) {
                    ++scenes;
                    try {
                        parse_scene_string(block, path);
                    } catch (const InputError& e) {
                        BOOST_ERROR(e.what());
                    }
                }
            }
        } else if (inside) {
            block += line + "\n";
        }
    }
    BOOST_TEST(!inside);
    BOOST_TEST(blocks > 0);
    BOOST_TEST(scenes > 0);
}

// --- [reference] ---------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(reference_section) {
    const std::string head = "[scene]\nname = \"x\"\n[parameters]\nw = 2\n[coordinates]\nq = { initial = 1 }\n"
                             "[lagrangian]\nT = \"q_dot^2/2\"\nV = \"w^2*q^2/2\"\n";  // 9 lines
    const Scene s = parse_scene_string(head + "[reference]\nq_dot = \"-w*sin(w*t)\"\nq = \"cos(w*t)\"\n", "t.toml");
    BOOST_TEST_REQUIRE(s.reference.has_value());
    BOOST_TEST_REQUIRE(s.reference->values.size() == 2u);
    BOOST_TEST(s.reference->values[0].state == "q_dot");  // file order
    BOOST_TEST(s.reference->values[1].state == "q");
    BOOST_TEST(s.reference->values[1].value.text == "cos(w*t)");
    check_pos(s.reference->values[1].value.pos, 12, 6);
    check_pos(s.reference->values[1].pos, 12, 1);
    BOOST_TEST(!parse_scene_string(head).reference.has_value());

    expect_error(head + "[reference]\nq = \"1\"\nqdot = \"0\"\n", 12, 1,
                 "'reference.qdot': qdot is not a state variable; did you mean 'q_dot'?");
    expect_error(head + "[reference]\nq = \"1\"\n", 10, 1,
                 "[reference] gives no value for 'q_dot'; a reference gives the whole state (q, q_dot)");
    expect_error(head + "[reference]\nq = \"1\"\nq_dot = [0]\n", 12, 9, "'reference.q_dot': expected an expression");
    expect_error("reference = 1\n" + head, 1, 13, "'reference': expected a table, got an integer");
}

// Reading /dev/zero, a FIFO with no writer or a huge file never ended: a scene is a regular
// file of at most 4 MiB, and the refusal comes before anything is read.
BOOST_AUTO_TEST_CASE(only_a_regular_file_of_bounded_size_is_read_as_a_scene) {
    const auto refusal = [](const std::string& path) {
        try {
            parse_scene_file(path);
        } catch (const InputError& e) {
            return e.message();
        }
        return std::string();
    };
    BOOST_TEST(refusal("/dev/zero") == "cannot read scene file '/dev/zero': it is not a regular file");
    const auto dir = std::filesystem::temp_directory_path() / "eomc_test_scene_bounded";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string fifo = (dir / "scene.fifo").string();
    BOOST_TEST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    BOOST_TEST(refusal(fifo) == "cannot read scene file '" + fifo + "': it is not a regular file");
    const std::string big = (dir / "big.toml").string();
    {
        std::ofstream out(big, std::ios::binary);
        out << "# " << std::string((4u << 20) + 10, 'x') << "\n";
    }
    BOOST_TEST(refusal(big) == "cannot read scene file '" + big + "': it is larger than 4 MiB");
    std::filesystem::remove_all(dir);
}
