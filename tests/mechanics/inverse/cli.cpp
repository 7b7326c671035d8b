// `eomc inverse` as a user meets it: the JSON shape for every classical case (checked by
// check_inverse_json.py), expressions in GiNaC syntax that parse back, the emitted
// [lagrangian] scene, LaTeX that compiles, exit codes and file:line:column errors for bad
// Newtonian scenes, and `eomc derive` on a Newtonian scene.
#define BOOST_TEST_MODULE inverse_cli
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "../support/command.hpp"

namespace fs = std::filesystem;

namespace {

using test_support::Result;
using test_support::slurp;

fs::path scratch(const std::string& name) { return test_support::scratch("inverse-scratch", name); }

Result run(const std::string& arguments, const fs::path& dir) { return test_support::run_eomc(arguments, dir); }

std::string scene(const std::string& relative) { return (fs::path(EOMC_SOURCE_DIR) / relative).string(); }

// The string value of "key" in a JSON text (GiNaC syntax has no quotes or backslashes to escape).
std::string json_value(const std::string& json, const std::string& key) {
    const std::string marker = "\"" + key + "\": \"";
    const auto at = json.find(marker);
    BOOST_REQUIRE(at != std::string::npos);
    const auto begin = at + marker.size();
    return json.substr(begin, json.find('"', begin) - begin);
}

// The quoted strings of the (possibly nested) array after "key" in a JSON text.
std::vector<std::string> json_strings(const std::string& json, const std::string& key) {
    const auto at = json.find("\"" + key + "\": [");
    BOOST_REQUIRE(at != std::string::npos);
    std::vector<std::string> out;
    int depth = 0;
    for (std::size_t i = json.find('[', at); i < json.size(); ++i) {
        if (json[i] == '[') ++depth;
        if (json[i] == ']' && --depth == 0) break;
        if (json[i] == '"') {
            const auto end = json.find('"', i + 1);
            out.push_back(json.substr(i + 1, end - i - 1));
            i = end;
        }
    }
    return out;
}

GiNaC::ex parse(const std::string& text, const std::vector<GiNaC::symbol>& symbols) {
    GiNaC::symtab names;
    for (const auto& s : symbols) names[s.get_name()] = s;
    GiNaC::parser reader(names, true);
    return reader(text);
}

}  // namespace

BOOST_AUTO_TEST_CASE(json_shape_of_every_classical_case) {
    const fs::path dir = scratch("json");
    struct Case {
        const char* scene;
        int n;
        const char *self_adjoint, *multiplier, *lagrangian;
    };
    const Case cases[] = {
        {"tests/mechanics/inverse/scenes/pendulum_fundamental.toml", 1, "true", "no", "yes"},
        {"scenes/damped_oscillator.toml", 1, "false", "yes", "yes"},
        {"tests/mechanics/inverse/scenes/central_force_polar.toml", 2, "false", "yes", "yes"},
        {"tests/mechanics/inverse/scenes/douglas_no_lagrangian.toml", 2, "false", "no", "no"},
        {"tests/mechanics/inverse/scenes/isotropic_oscillator.toml", 2, "true", "no", "yes"},
    };
    for (const Case& c : cases) {
        BOOST_TEST_CONTEXT(c.scene) {
            const fs::path out = dir / (fs::path(c.scene).stem().string() + ".json");
            const Result r = run("inverse " + scene(c.scene) + " --format json -o " + out.string(), dir);
            BOOST_TEST_REQUIRE(r.status == 0, r.err);
            const std::string command = "python3 " + scene("tests/mechanics/inverse/check_inverse_json.py") + " " + out.string() +
                                        " " + std::to_string(c.n) + " " + c.self_adjoint + " " + c.multiplier + " " +
                                        c.lagrangian + " > " + (dir / "check.log").string() + " 2>&1";
            BOOST_TEST(std::system(command.c_str()) == 0, slurp(dir / "check.log"));
        }
    }
}

BOOST_AUTO_TEST_CASE(json_expressions_parse_back_with_ginac) {
    const fs::path dir = scratch("parse_back");
    const Result r = run("inverse " + scene("scenes/damped_oscillator.toml") + " --format json", dir);
    BOOST_REQUIRE(r.status == 0);
    const GiNaC::symbol t("t"), x("x"), xd("x_dot"), gamma("gamma"), w("w");
    const std::vector<GiNaC::symbol> symbols{t, x, xd, gamma, w};
    const GiNaC::ex L = parse(json_value(r.out, "lagrangian"), symbols);
    const GiNaC::ex expected = GiNaC::exp(gamma * t) * (xd * xd - w * w * x * x) / 2;
    BOOST_TEST((L - expected).expand().is_zero(), "L = " << L);
    const auto g = json_strings(r.out, "multiplier");
    BOOST_REQUIRE(g.size() == 1u);
    BOOST_TEST((parse(g[0], symbols) - GiNaC::exp(gamma * t)).is_zero(), g[0]);
    BOOST_TEST(json_value(r.out, "name") == "S3");  // the one condition of one degree of freedom
    const std::string residual = json_value(r.out, "residual");
    BOOST_TEST((parse(residual, symbols) - 2 * gamma).is_zero(), residual);
}

BOOST_AUTO_TEST_CASE(emitted_scene_is_a_lagrangian_scene_eomc_accepts) {
    const fs::path dir = scratch("emit");
    const fs::path emitted = dir / "polar_lagrangian.toml";
    const Result r = run("inverse " + scene("tests/mechanics/inverse/scenes/central_force_polar.toml") + " --emit-scene " +
                             emitted.string() + " -o " + (dir / "report.txt").string(),
                         dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string text = slurp(emitted);
    BOOST_TEST(text.find("[lagrangian]") != std::string::npos);
    BOOST_TEST(text.find("name = \"central_force_polar_lagrangian\"") != std::string::npos);
    BOOST_TEST(text.find("theta = { initial = 0, rate = 1.2 }") != std::string::npos);
    const Result d = run("derive " + emitted.string() + " --format json", dir);
    BOOST_TEST_REQUIRE(d.status == 0, d.err);
    // The Lagrangian scene has the energy of the central-force problem as its invariant.
    BOOST_TEST(d.out.find("\"invariants\": {\"energy\": ") != std::string::npos);
    const std::string report = slurp(dir / "report.txt");
    BOOST_TEST(report.find("Multiplier (diagonal in q): g = [[1, 0], [0, r^2]]") != std::string::npos, report);
}

BOOST_AUTO_TEST_CASE(no_scene_is_emitted_without_a_lagrangian) {
    const fs::path dir = scratch("refuse");
    const fs::path emitted = dir / "none.toml";
    const Result r = run("inverse " + scene("tests/mechanics/inverse/scenes/douglas_no_lagrangian.toml") + " --emit-scene " +
                             emitted.string() + " -o " + (dir / "report.txt").string(),
                         dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("no verified Lagrangian to write") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("no regular Lagrangian exists") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(emitted));
    BOOST_TEST(!fs::exists(dir / "report.txt"));  // nothing written on failure
}

BOOST_AUTO_TEST_CASE(text_report_names_the_verdict_and_the_reasoning) {
    const fs::path dir = scratch("text");
    const Result douglas = run("inverse " + scene("tests/mechanics/inverse/scenes/douglas_no_lagrangian.toml"), dir);
    BOOST_REQUIRE(douglas.status == 0);
    BOOST_TEST(douglas.out.find("Verdict: not self-adjoint — S3(x,y) = 1 ≠ 0") != std::string::npos, douglas.out);
    BOOST_TEST(douglas.out.find("so g_x_y = 0") != std::string::npos);
    BOOST_TEST(douglas.out.find("so g_x_x = 0") != std::string::npos);
    BOOST_TEST(douglas.out.find("No regular Lagrangian exists.") != std::string::npos);
    const Result iso = run("inverse " + scene("tests/mechanics/inverse/scenes/isotropic_oscillator.toml"), dir);
    BOOST_REQUIRE(iso.status == 0);
    BOOST_TEST(iso.out.find("Verdict: self-adjoint") != std::string::npos);
    BOOST_TEST(iso.out.find("A second Lagrangian, from the constant multiplier g = [[0, 1], [1, 0]]") != std::string::npos,
               iso.out);
}

BOOST_AUTO_TEST_CASE(latex_report_compiles_with_pdflatex) {
    const fs::path dir = scratch("latex");
    for (const char* s : {"scenes/damped_oscillator.toml", "tests/mechanics/inverse/scenes/douglas_no_lagrangian.toml",
                          "tests/mechanics/inverse/scenes/isotropic_oscillator.toml"}) {
        const std::string stem = fs::path(s).stem().string();
        const Result r = run("inverse " + scene(s) + " --format latex -o " + (dir / (stem + ".tex")).string(), dir);
        BOOST_REQUIRE(r.status == 0);
        const std::string command = "cd " + dir.string() + " && pdflatex -interaction=nonstopmode -halt-on-error " +
                                    stem + ".tex > " + stem + ".pdflatex.log 2>&1";
        BOOST_TEST(std::system(command.c_str()) == 0, "pdflatex failed on " << stem << ", see " << dir);
    }
    // `eomc derive` of a Newtonian scene in LaTeX too.
    const Result r = run("derive " + scene("tests/mechanics/inverse/scenes/pendulum_fundamental.toml") + " --format latex -o " +
                             (dir / "derive.tex").string(),
                         dir);
    BOOST_REQUIRE(r.status == 0);
    const std::string command = "cd " + dir.string() +
                                " && pdflatex -interaction=nonstopmode -halt-on-error derive.tex > derive.pdflatex.log 2>&1";
    BOOST_TEST(std::system(command.c_str()) == 0, "pdflatex failed on derive.tex, see " << dir);
}

BOOST_AUTO_TEST_CASE(bad_newtonian_scene_exits_2_at_the_place) {
    const fs::path dir = scratch("bad");
    const fs::path file = dir / "bad.toml";
    std::ofstream(file) << "[scene]\nname = \"bad\"\n[parameters]\ngamma = 1\n[coordinates]\nx = {}\n"
                           "[newtonian]\nx_ddot = \"-gamma*x_dot - omega^2*x\"\n";
    const Result r = run("inverse " + file.string() + " -o " + (dir / "out.txt").string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find(file.string() + ":8:26: error: unknown symbol 'omega'") == 0u, r.err);
    BOOST_TEST(!fs::exists(dir / "out.txt"));
}

BOOST_AUTO_TEST_CASE(derive_on_a_newtonian_scene_prints_both_forms) {
    const fs::path dir = scratch("derive");
    const Result r = run("derive " + scene("tests/mechanics/inverse/scenes/pendulum_fundamental.toml"), dir);
    BOOST_REQUIRE(r.status == 0);
    BOOST_TEST(r.out.find("Kinematic form q̈ = f(t, q, q̇) (solved from the fundamental form)") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("Fundamental form A(t, q, q̇) q̈ + B(t, q, q̇) = 0 (as given)") != std::string::npos);
    BOOST_TEST(r.out.find("Equations of motion M q̈ = f") != std::string::npos);
    const Result pj = run("derive " + scene("tests/mechanics/inverse/scenes/pendulum_fundamental.toml") + " --format json", dir);
    BOOST_REQUIRE(pj.status == 0);
    const GiNaC::symbol m("m"), l("l"), g("g"), theta("theta");
    const std::vector<GiNaC::symbol> symbols{m, l, g, theta};
    const auto kinematic = json_strings(pj.out, "kinematic");
    BOOST_REQUIRE(kinematic.size() == 1u);
    BOOST_TEST((parse(kinematic[0], symbols) + g / l * GiNaC::sin(theta)).normal().is_zero(), kinematic[0]);
    const auto M = json_strings(pj.out, "mass_matrix");
    BOOST_REQUIRE(M.size() == 1u);
    BOOST_TEST((parse(M[0], symbols) - m * l * l).is_zero(), M[0]);
    const Result j = run("derive " + scene("scenes/damped_oscillator.toml") + " --format json", dir);
    BOOST_REQUIRE(j.status == 0);
    BOOST_TEST(j.out.find("\"form\": \"kinematic\"") != std::string::npos);
    std::ofstream(dir / "d.json") << j.out;
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "d.json").string() + " > /dev/null").c_str()) == 0);
}

BOOST_AUTO_TEST_CASE(leo_drag_ends_with_a_verdict_within_the_default_budget) {
    // It used to run past 600 s in the multiplier search (normal() on ∇Φ of drag under J2).
    const fs::path dir = scratch("leo_drag");
    const Result r = run("inverse " + scene("scenes/leo_drag.toml"), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("Verdict: not self-adjoint — S3(x,x)") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("The algebraic conditions close at rank") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("Conclusion: not self-adjoint") != std::string::npos, r.out);
}

BOOST_AUTO_TEST_CASE(undecided_search_is_reported_in_text_latex_and_json) {
    const fs::path dir = scratch("undecided");
    const std::string args = "inverse " + scene("scenes/leo_drag.toml") + " --search-budget 10000";
    const Result text = run(args, dir);
    BOOST_TEST_REQUIRE(text.status == 0, text.err);
    // The node count depends on the form GiNaC keeps Φ in, which follows its hash order and so
    // differs between builds of eomc (the sanitizer build's is another); it must exceed the budget.
    const std::string head = "  Undecided: the algebraic consequences of H1–H2 were cut after Φ (rank 2 of 6): it has ";
    const auto at = text.out.find(head);
    BOOST_TEST_REQUIRE(at != std::string::npos, text.out);
    std::size_t nodes = 0;
    std::istringstream(text.out.substr(at + head.size())) >> nodes;
    BOOST_TEST(nodes > 10000u);
    BOOST_TEST(text.out.find(" expression nodes, over the budget of 10000", at) != std::string::npos, text.out);
    BOOST_TEST(text.out.find("; the multiplier search is undecided: ") != std::string::npos);

    const Result json = run(args + " --format json -o " + (dir / "leo.json").string(), dir);
    BOOST_TEST_REQUIRE(json.status == 0, json.err);
    const std::string shape = "python3 " + scene("tests/mechanics/inverse/check_inverse_json.py") + " " + (dir / "leo.json").string() +
                              " 3 false no no > " + (dir / "check.log").string() + " 2>&1";
    BOOST_TEST(std::system(shape.c_str()) == 0, slurp(dir / "check.log"));
    const std::string undecided =
        "python3 -c \"import json,sys; d=json.load(open(sys.argv[1])); m=d['multiplier_search']; "
        "assert m['undecided'].startswith('the algebraic consequences'), m['undecided']; "
        "assert m['singular_forced'] is False and m['kind'] is None; "
        "assert 'the multiplier search is undecided' in d['reason']\" " +
        (dir / "leo.json").string() + " > " + (dir / "undecided.log").string() + " 2>&1";
    BOOST_TEST(std::system(undecided.c_str()) == 0, slurp(dir / "undecided.log"));

    const Result latex = run(args + " --format latex -o " + (dir / "leo.tex").string(), dir);
    BOOST_TEST_REQUIRE(latex.status == 0, latex.err);
    BOOST_TEST(slurp(dir / "leo.tex").find("Undecided: the algebraic consequences") != std::string::npos);
    const std::string compile = "cd " + dir.string() +
                                " && pdflatex -interaction=nonstopmode -halt-on-error leo.tex > leo.pdflatex.log 2>&1";
    BOOST_TEST(std::system(compile.c_str()) == 0, "pdflatex failed on leo.tex, see " << dir);
}
