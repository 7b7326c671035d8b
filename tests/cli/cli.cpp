#define BOOST_TEST_MODULE cli
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "command.hpp"

namespace fs = std::filesystem;

namespace {

using test_support::Result;
using test_support::slurp;

// A scratch directory per test case, emptied first.
fs::path scratch(const std::string& name) { return test_support::scratch("cli-scratch", name); }

Result run(const std::string& arguments, const fs::path& dir) { return test_support::run_eomc(arguments, dir); }

using test_support::write_scene;

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    BOOST_REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

std::size_t files_in(const fs::path& dir) {
    return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

const char* tube = R"([scene]
name = "tube"
[parameters]
m = 0.5
Omega = 3.0
[coordinates]
q = { initial = 0.1 }
[carrier]
angular_velocity = ["0", "Omega", "0"]
[[body]]
name = "ball"
mass = "m"
position = ["q", "0", "0"]
)";

// Every bad input: exit 2, a diagnostic at the exact place, no output file.
void expect_input_error(const std::string& scene, const std::string& where, const std::string& message) {
    const fs::path dir = scratch("bad");
    const fs::path file = write_scene(dir, scene);
    const fs::path out = dir / "out";
    const Result r = run("generate " + file.string() + " -o " + out.string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.rfind(file.string() + ":" + where + ": error: ", 0) == 0, "stderr: " << r.err);
    BOOST_TEST(r.err.find(message) != std::string::npos, "stderr: " << r.err);
    BOOST_TEST(!fs::exists(out));
}

}  // namespace

BOOST_AUTO_TEST_CASE(bad_scenes_are_refused_with_their_place) {
    expect_input_error("[scene\nname = \"x\"\n", "1:7", "invalid TOML");
    expect_input_error(std::string(tube) + "[effects]\nkeep = [\"coriollis\"]\n", "15:9", "did you mean 'coriolis'");
    // position = ["q", "…", "0"] is line 13; its second component starts in column 19.
    expect_input_error(replaced(tube, R"(["q", "0", "0"])", R"(["q", "qq", "0"])"), "13:19", "unknown symbol 'qq'");
    expect_input_error(replaced(tube, R"(["q", "0", "0"])", R"(["q", "p_dot", "0"])"), "13:19",
                       "'p' is not a declared coordinate");
    expect_input_error(replaced(tube, R"(["q", "0", "0"])", R"(["q", "q_dot", "0"])"), "13:19",
                       "may not appear in the position");
    // The place is the character where parsing stopped: the end of "Omega*(".
    expect_input_error(replaced(tube, R"("Omega", "0"])", R"("Omega*(", "0"])"), "9:34", "cannot parse");
    expect_input_error(replaced(tube, "m = 0.5", "m = -0.5"), "12:9", "must be positive");
    expect_input_error(replaced(tube, "[carrier]\n", "[carrier]\nmotion = \"free\"\n"), "8:1", "missing required key 'mass'");
    expect_input_error(replaced(tube, "[carrier]\n", "[carrier]\nmotion = \"free\"\nmass = \"m\"\ninertia = [\"1\", \"1\", \"1\"]\n"),
                       "12:27", "clashes with a name already declared");
    expect_input_error(replaced(tube, "[[body]]", "[[bodyy]]"), "10:3", "bodyy");
}

BOOST_AUTO_TEST_CASE(a_singular_mass_matrix_names_the_coordinates) {
    expect_input_error(R"([scene]
name = "degenerate"
[coordinates]
x = {}
y = {}
[lagrangian]
T = "(x_dot + y_dot)^2/2"
)", "7:6", "'x', 'y'");
}

BOOST_AUTO_TEST_CASE(bad_overrides_and_missing_files) {
    const fs::path dir = scratch("overrides");
    const fs::path file = write_scene(dir, tube);
    Result r = run("simulate " + file.string() + " --set Omgea=2 --cache-dir " + (dir / "cache").string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("Omgea") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("did you mean 'Omega'") != std::string::npos, r.err);  // a swap is one typo
    r = run("simulate " + file.string() + " --set Omega=abc", dir);
    BOOST_TEST(r.status == 2);
    r = run("derive " + (dir / "missing.toml").string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("cannot open") != std::string::npos, r.err);
}

BOOST_AUTO_TEST_CASE(a_failed_integration_exits_nonzero_and_keeps_the_rows_so_far) {
    // q̈ = q³·4 from q = 1 blows up at t ≈ 0.927 (∫ dq / sqrt(2 q⁴ − 2)).
    const fs::path dir = scratch("blowup");
    const fs::path file = write_scene(dir, R"([scene]
name = "blowup"
[coordinates]
q = { initial = 1.0, rate = 0.0 }
[lagrangian]
T = "q_dot^2/2"
V = "-q^4"
)");
    const Result r = run("simulate " + file.string() + " --t-end 2 --output " + (dir / "x.csv").string() +
                             " --cache-dir " + (dir / "cache").string(), dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("eomc: error:") == 0u, r.err);
    BOOST_TEST(r.err.find("x.csv holds the ") != std::string::npos, r.err);
    BOOST_TEST(slurp(dir / "x.csv").rfind("t,q,q_dot", 0) == 0u);
}

BOOST_AUTO_TEST_CASE(derive_json_is_parseable_and_holds_the_seed_equation) {
    const fs::path dir = scratch("json");
    const Result r = run("derive " + (fs::path(EOMC_SOURCE_DIR) / "scenes/disk_tube_ball.toml").string() +
                             " --format json -o " + (dir / "d.json").string(), dir);
    BOOST_REQUIRE(r.status == 0);
    const std::string json = slurp(dir / "d.json");
    BOOST_TEST(json.find("\"coordinates\": [\"q\"]") != std::string::npos);
    BOOST_TEST(json.find("\"mass_matrix\": [[\"m\"]]") != std::string::npos);
    BOOST_TEST(json.find("\"centrifugal\": \"") != std::string::npos);
    BOOST_TEST(json.find("\"invariants\": {\"energy\": \"") != std::string::npos);
    // A real JSON parser must accept it.
    const int rc = std::system(("python3 -m json.tool " + (dir / "d.json").string() + " > /dev/null").c_str());
    BOOST_TEST(rc == 0);
}

BOOST_AUTO_TEST_CASE(derive_latex_compiles_with_pdflatex) {
    const fs::path dir = scratch("latex");
    for (const char* scene : {"disk_tube_ball", "foucault_pendulum", "double_pendulum", "pendulum_cartesian",
                              "chaplygin_sleigh"}) {
        const fs::path tex = dir / (std::string(scene) + ".tex");
        const Result r = run("derive " + (fs::path(EOMC_SOURCE_DIR) / "scenes" / (std::string(scene) + ".toml")).string() +
                                 " --format latex -o " + tex.string(), dir);
        BOOST_REQUIRE(r.status == 0);
        const std::string command = "cd " + dir.string() + " && pdflatex -interaction=nonstopmode -halt-on-error " +
                                    tex.filename().string() + " > " + scene + ".pdflatex.log 2>&1";
        BOOST_TEST(std::system(command.c_str()) == 0, "pdflatex failed on " << scene << ", see " << dir);
        BOOST_TEST(fs::exists(dir / (std::string(scene) + ".pdf")));
    }
}

// A constrained scene: the commands that cannot carry the rows refuse them at the row's place.
BOOST_AUTO_TEST_CASE(commands_that_cannot_carry_constraints_refuse_them) {
    const fs::path dir = scratch("constraints");
    const std::string scene = (fs::path(EOMC_SOURCE_DIR) / "scenes/pendulum_cartesian.toml").string();
    for (const char* command : {"derive --hamiltonian", "inverse", "equilibria", "generate --variational -o ."}) {
        const Result r = run(std::string(command) + " " + scene, dir);
        BOOST_TEST(r.status == 2, command);
        BOOST_TEST(r.err.find("pendulum_cartesian.toml:25:14: error:") != std::string::npos, command << ": " << r.err);
        BOOST_TEST(r.err.find("'rod'") != std::string::npos, command << ": " << r.err);
    }
    BOOST_TEST(!fs::exists(dir / "pendulum_cartesian.hpp"));
}

BOOST_AUTO_TEST_CASE(run_does_the_whole_job_on_the_default_scene) {
    const fs::path dir = scratch("run");
    const Result r = run("run " + (fs::path(EOMC_SOURCE_DIR) / "scenes/disk_tube_ball.toml").string() + " -d " +
                             dir.string() + " --cache-dir " + (dir / "cache").string(),
                         dir);
    BOOST_REQUIRE(r.status == 0);
    BOOST_TEST(r.out.find("T_e") != std::string::npos);
    BOOST_TEST(r.out.find("centrifugal") != std::string::npos);
    BOOST_TEST(fs::exists(dir / "disk_tube_ball.hpp"));
    const std::string csv = slurp(dir / "disk_tube_ball.csv");
    BOOST_TEST(csv.rfind("t,q,q_dot,energy,holding_force_1,holding_force_2,holding_force_3,holding_moment_1,"
                          "holding_moment_2,holding_moment_3\n",
                          0) == 0u);
    BOOST_TEST(files_in(dir) == 3u);  // header, CSV, cache
}

BOOST_AUTO_TEST_CASE(the_readme_example_derives_as_the_readme_says) {
    // README.md's scene is the contract users copy first: it must parse and give the
    // equation the README states, m q̈ − m Ω² q = 0, with the Jacobi integral proven.
    const std::string readme = slurp(fs::path(EOMC_SOURCE_DIR) / "README.md");
    const auto start = readme.find("```toml\n");
    BOOST_REQUIRE(start != std::string::npos);
    const auto end = readme.find("```", start + 8);
    const fs::path dir = scratch("readme");
    const fs::path file = write_scene(dir, readme.substr(start + 8, end - start - 8));
    const Result r = run("derive " + file.string() + " --format json", dir);
    BOOST_REQUIRE(r.status == 0);
    BOOST_TEST(r.out.find("\"mass_matrix\": [[\"m\"]]") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("\"invariants\": {\"energy\": \"") != std::string::npos, r.out);
    const Result text = run("derive " + file.string(), dir);
    BOOST_TEST(text.out.find("T_m = Σ m (v_o + ω × r')·ṙ'  = 0") != std::string::npos, text.out);
}

BOOST_AUTO_TEST_CASE(equilibria_json_lists_the_hoop_equilibria) {
    const fs::path dir = scratch("equilibria");
    const Result r = run("equilibria " + (fs::path(EOMC_SOURCE_DIR) / "scenes/bead_on_hoop.toml").string() +
                             " --format json", dir);
    BOOST_REQUIRE(r.status == 0);
    std::ofstream(dir / "e.json") << r.out;
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "e.json").string() + " > /dev/null").c_str()) == 0);
    std::size_t count = 0;
    for (auto at = r.out.find("\"verdict\""); at != std::string::npos; at = r.out.find("\"verdict\"", at + 1)) ++count;
    BOOST_TEST(count == 4u);  // −θ*, 0, θ*, π (θ = −π is θ = π)
    BOOST_TEST(r.out.find("\"verdict\": \"stable\"") != std::string::npos);
    // The closed forms ride along in GiNaC syntax, compared as expressions: the order GiNaC
    // prints terms in follows its hash values, which differ between builds of eomc.
    GiNaC::symbol g("g"), omega("omega"), R("R");
    GiNaC::symtab names{{"g", g}, {"omega", omega}, {"R", R}};
    const auto printed = [&](const std::string& key) {
        std::vector<GiNaC::ex> out;
        for (auto at = r.out.find(key); at != std::string::npos; at = r.out.find(key, at + 1)) {
            const auto open = r.out.find('"', at + key.size()) + 1;
            out.push_back(GiNaC::parser(names)(r.out.substr(open, r.out.find('"', open) - open)));
        }
        return out;
    };
    const auto contains = [](const std::vector<GiNaC::ex>& all, const GiNaC::ex& e) {
        return std::any_of(all.begin(), all.end(), [&](const GiNaC::ex& x) { return (x - e).expand().is_zero(); });
    };
    BOOST_TEST(contains(printed("\"exact\": {\"theta\": "), GiNaC::acos(g / (omega * omega * R))), r.out);
    BOOST_TEST(contains(printed("\"lambda_squared\": "), (omega * omega * R - g) / R), r.out);
}

BOOST_AUTO_TEST_CASE(every_integrator_closes_the_kepler_orbit) {
    // After one period the orbit is back at pericentre, r = a(1 − e) = 0.5. With h = 1e-3
    // (fixed step) or tolerance 1e-12 (adaptive) every method here is accurate to ~1e-12
    // (RK4: C h⁴ with C ~ 1; Gauss–Legendre and DOP853 far better). 1e-8 leaves four orders
    // of margin and still fails for a wrong tableau, whose error would be O(h) ~ 1e-3.
    // radau5 runs its Newton iteration and error test at its own tolerance 0.1 rtol^(2/3) ≈ 1e-9
    // (Hairer & Wanner's RADAU5 convention), about 460 steps here: its bound is that
    // tolerance summed over the steps, 5e-7, so 1e-6; a wrong coefficient still gives O(h).
    const fs::path dir = scratch("integrators");
    for (const char* method : {"rk4", "dopri5", "dop853", "radau5", "gl4", "gl6", "gl8"}) {
        const Result r = run("simulate " + (fs::path(EOMC_SOURCE_DIR) / "scenes/kepler_orbit.toml").string() +
                                 " --integrator " + method + " --step 1e-3 --rtol 1e-12 --atol 1e-12 --summary json" +
                                 " --cache-dir " + (dir / "cache").string(),
                             dir);
        BOOST_REQUIRE_MESSAGE(r.status == 0, method << ": " << r.err);
        const auto at = r.out.find("\"r\": ");
        BOOST_REQUIRE(at != std::string::npos);
        const double radius = std::stod(r.out.substr(at + 5));
        const double bound = std::string(method) == "radau5" ? 1e-6 : 1e-8;
        BOOST_TEST(std::abs(radius - 0.5) < bound, method << ": r = " << radius);
    }
}

namespace {

// A throw with its apex and a terminal landing: y = 7 t − 9.81 t²/2 lands at t = 14/9.81.
const char* throw_scene = R"toml([scene]
name = "throw"
[parameters]
g = 9.81
[coordinates]
x = { initial = 0.0, rate = 3.0 }
y = { initial = 0.0, rate = 7.0 }
[lagrangian]
T = "(x_dot^2 + y_dot^2)/2"
V = "g*y"
[simulate]
integrator = "dop853"
t_end = 10
[events]
apex = { when = "y_dot", direction = "down" }
ground = { when = "y", direction = "down", terminal = true }
)toml";

}  // namespace

BOOST_AUTO_TEST_CASE(bad_events_are_refused_with_their_place) {
    // ground is line 16, its expression "y" starts in column 20; apex is line 15.
    expect_input_error(replaced(throw_scene, R"(when = "y",)", R"(when = "yy",)"), "16:20",
                       "unknown symbol 'yy' in event 'ground'; did you mean 'y'?");
    expect_input_error(replaced(throw_scene, R"(direction = "down", terminal)", R"(direction = "dwon", terminal)"),
                       "16:36", "did you mean 'down'?");
    expect_input_error(replaced(throw_scene, "terminal = true", "terminal = 1"), "16:55", "expected true or false");
    expect_input_error(replaced(throw_scene, "terminal = true", "terminl = true"), "16:44", "did you mean 'terminal'?");
    expect_input_error(replaced(throw_scene, R"(when = "y_dot")", R"(when = "y_ddot")"), "15:18",
                       "'y_ddot' is an acceleration, which may not appear in event 'apex'");
}

BOOST_AUTO_TEST_CASE(a_terminal_event_stops_the_run_with_exit_0) {
    const fs::path dir = scratch("events");
    const fs::path file = write_scene(dir, throw_scene);
    const Result r = run("simulate " + file.string() + " --output " + (dir / "t.csv").string() + " --cache-dir " +
                             (dir / "cache").string(),
                         dir);
    BOOST_REQUIRE_MESSAGE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("stopped by the terminal event 'ground'") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("events      2 located") != std::string::npos, r.out);
    const std::string csv = slurp(dir / "t.csv");
    // x is cyclic: its momentum is tracked beside the energy (mechanics/rigid/cyclic).
    BOOST_TEST(csv.rfind("t,x,y,x_dot,y_dot,energy,momentum_x,event\n", 0) == 0u, csv.substr(0, 60));
    BOOST_TEST(csv.find(",apex\n") != std::string::npos);
    // The last row is the landing, at t = 14/9.81 to round-off.
    const std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    BOOST_TEST(last.substr(last.size() - 7) == "ground\n");
    BOOST_TEST(std::abs(std::stod(last) - 14 / 9.81) <= 1e-14);
    // JSON: the events and what stopped the run, valid JSON.
    const Result j = run("simulate " + file.string() + " --summary json --cache-dir " + (dir / "cache").string(), dir);
    BOOST_REQUIRE(j.status == 0);
    BOOST_TEST(j.out.find("\"stopped_by\": \"ground\"") != std::string::npos, j.out);
    std::ofstream(dir / "s.json") << j.out;
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "s.json").string() + " > /dev/null").c_str()) == 0);
}

BOOST_AUTO_TEST_CASE(splitting_methods_need_a_separable_scene) {
    const fs::path dir = scratch("splitting");
    // The damped oscillator's force depends on q_dot: not separable.
    const fs::path file = write_scene(dir, R"toml([scene]
name = "damped"
[coordinates]
q = { initial = 1.0 }
[lagrangian]
T = "q_dot^2/2"
V = "q^2/2"
[forces]
generalized = { q = "-q_dot/10" }
[simulate]
integrator = "kahanli8"
)toml");
    Result r = run("simulate " + file.string() + " --output " + (dir / "d.csv").string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.rfind(file.string() + ":11:14: error: the kahanli8 integrator needs a separable system", 0) == 0u,
               r.err);
    BOOST_TEST(!fs::exists(dir / "d.csv"));
    r = run("run " + file.string() + " -d " + (dir / "out").string() + " --integrator verlet", dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.rfind("--integrator: error: the verlet integrator needs a separable system", 0) == 0u, r.err);
    BOOST_TEST(!fs::exists(dir / "out"));
    // On a separable scene they run; bad option values are bad input too.
    const fs::path tube_file = write_scene(dir, tube);
    r = run("simulate " + tube_file.string() + " --integrator yoshida6 --step 0.01 --t-end 1 --compensated off "
            "--cache-dir " + (dir / "cache").string(),
            dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.out.find("yoshida6 (step 0.01)") != std::string::npos, r.out);
    r = run("simulate " + tube_file.string() + " --compensated maybe", dir);
    BOOST_TEST(r.status == 2);
}

// jacobian() is emitted only when asked for: --jacobian, [kernel] jacobian = true, --variational;
// the kernel says which (has_jacobian) and so does its banner. A bad [kernel] key is refused at its place.
BOOST_AUTO_TEST_CASE(the_jacobian_is_generated_only_when_asked_for) {
    const fs::path dir = scratch("jacobian");
    const auto generate = [&](const std::string& scene, const std::string& flags) {
        const fs::path file = write_scene(dir, scene);
        const Result r = run("generate " + file.string() + " -o " + (dir / "out").string() + flags, dir);
        BOOST_TEST_REQUIRE(r.status == 0, "stderr: " << r.err);
        return slurp(dir / "out" / "tube.hpp");
    };
    // The banner's text with its comment lines joined.
    const auto banner = [](const std::string& header) {
        std::string text = header.substr(0, header.find("#pragma once"));
        for (std::size_t at; (at = text.find("\n// ")) != std::string::npos;) text.replace(at, 4, 1, ' ');
        return text;
    };
    const std::string plain = generate(tube, "");
    BOOST_TEST(plain.find("has_jacobian = false") != std::string::npos);
    BOOST_TEST(plain.find("static void jacobian(") == std::string::npos);
    BOOST_TEST(banner(plain).find("No jacobian() (eomc generate --jacobian adds it).") != std::string::npos);
    for (const auto& [scene, flags] : {std::pair<std::string, std::string>{tube, " --jacobian"},
                                       {std::string(tube) + "[kernel]\njacobian = true\n", ""},
                                       {tube, " --variational"}}) {
        const std::string header = generate(scene, flags);
        BOOST_TEST(header.find("has_jacobian = true") != std::string::npos, flags);
        BOOST_TEST(header.find("static void jacobian(") != std::string::npos, flags);
        BOOST_TEST(banner(header).find("jacobian() gives ∂ẋ/∂x.") != std::string::npos, flags);
    }
    expect_input_error(std::string(tube) + "[kernel]\njacobian = \"yes\"\n", "15:12", "expected true or false");
    expect_input_error(std::string(tube) + "[kernel]\njacobain = true\n", "15:1", "did you mean 'jacobian'");
}
