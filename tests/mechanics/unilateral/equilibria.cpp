// The KKT equilibria of Mei §6.4 (mechanics/unilateral/equilibria) against answers known by hand:
// the pendulum leaning on a wall (λ = m g l sin θ_w), the same wall behind the bottom (θ = 0,
// interior, the wall's λ < 0 refused), the wall through the bottom (λ = 0: degenerate), a particle
// on a table (λ = m g, x free), in a V-shaped trough (two active rows), under a ceiling (λ < 0
// refused), on and in a circle (the curvature of the gap decides); the refusals at the row; and
// `eomc equilibria` in text, JSON (parsed by python3) and LaTeX.
//
// Tolerances: the closed-form points are the closed forms evaluated in double (a few ulp); Newton's
// points converge until the step is 1e-13 relative, quadratically, so they too are at round-off:
// 1e-12 relative on q and λ throughout.
#define BOOST_TEST_MODULE mechanics_unilateral_equilibria
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <ginac/ginac.h>

#include "mechanics/derive.hpp"
#include "mechanics/unilateral/equilibria.hpp"
#include "model/model.hpp"
#include "support/diagnostic.hpp"

#include "command.hpp"
#include "scenes.hpp"

namespace u = eomc::mechanics::unilateral;
using eomc::model::Model;
using test_support::Result;

namespace {

constexpr double g = 9.81, l = 0.5, deg = std::numbers::pi / 180;

u::UnilateralEquilibria kkt(const std::string& toml) {
    const Model model = test_support::model_of(toml, "kkt.toml");
    return u::kkt_equilibria(model, eomc::mechanics::derive(model));
}

// The bundled leaning pendulum with the wall at θ_w (radians).
std::string pendulum(double theta_w) {
    std::string text = test_support::bundled_scene("pendulum_leaning_wall");
    const std::string line = "theta_w = 0.17453292519943295";
    const auto at = text.find(line);
    BOOST_REQUIRE(at != std::string::npos);
    return text.replace(at, line.size(), fmt::format("theta_w = {:.17g}", theta_w));
}

std::string particle(const std::string& parameters, const std::string& V, const std::string& rows, double x0, double y0) {
    return "[scene]\nname = \"particle\"\n[parameters]\n" + parameters + "\n[coordinates]\nx = { initial = " +
           fmt::format("{:.17g}", x0) + " }\ny = { initial = " + fmt::format("{:.17g}", y0) + " }\n[lagrangian]\nT = \"m*(x_dot^2 + y_dot^2)/2\"\nV = \"" +
           V + "\"\n" + rows;
}

std::string gap(const std::string& name, const std::string& f) {
    return "[[unilateral]]\nname = \"" + name + "\"\ngap = \"" + f + "\"\nrestitution = \"0.5\"\n";
}

bool same(const GiNaC::ex& a, const GiNaC::ex& b) { return GiNaC::normal((a - b).expand()).is_zero(); }

const GiNaC::symbol& symbol_named(const Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    throw std::runtime_error("no parameter " + name);
}

int stable_count(const u::UnilateralEquilibria& found) {
    int n = 0;
    for (const auto& e : found.equilibria) n += e.verdict == "stable";
    return n;
}

}  // namespace

// θ ≥ θ_w = 10°: V' = m g l sin θ > 0 at the wall, so the pendulum leans on it with λ = m g l sin θ_w,
// stable on first order alone (one coordinate, λ > 0). The bottom θ = 0 violates the gap; the top
// θ = π is an interior equilibrium, a maximum of V.
BOOST_AUTO_TEST_CASE(pendulum_leaning_on_a_wall) {
    const Model model = test_support::bundled_model("pendulum_leaning_wall");
    const auto found = u::kkt_equilibria(model, eomc::mechanics::derive(model));
    BOOST_REQUIRE(found.rows.size() == 1u);
    BOOST_TEST(stable_count(found) == 1);
    BOOST_REQUIRE(found.equilibria.size() == 2u);
    const auto& wall = found.equilibria[0];
    BOOST_TEST(wall.point.q[0] == 10 * deg, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(u::name(wall.kind) == std::string("boundary"));
    BOOST_TEST(wall.verdict == "stable");
    BOOST_TEST(wall.point.active[0]);
    BOOST_TEST(wall.point.lambda[0] == 0.851744311456293, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(wall.curvature.empty());  // the tangent space is {0}
    BOOST_REQUIRE(wall.point.exact_lambda.size() == 1u);
    const auto &m_ = symbol_named(model, "m"), &g_ = symbol_named(model, "g"), &l_ = symbol_named(model, "l"),
               &w_ = symbol_named(model, "theta_w");
    BOOST_TEST(same(wall.point.exact_lambda[0], m_ * g_ * l_ * GiNaC::sin(w_)), wall.point.exact_lambda[0]);
    BOOST_TEST(same(wall.point.exact_q[0], w_));
    BOOST_TEST(same(*found.potential, -m_ * g_ * l_ * GiNaC::cos(model.coordinates[0].q)));

    const auto& top = found.equilibria[1];
    BOOST_TEST(top.point.q[0] == std::numbers::pi, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(u::name(top.kind) == std::string("interior"));
    BOOST_TEST(top.verdict == "unstable");
    BOOST_REQUIRE(top.curvature.size() == 1u);
    BOOST_TEST(top.curvature[0] == -g * l, boost::test_tools::tolerance(1e-12));  // V'' = m g l cos π

    // The bottom, refused: the gap there is −θ_w.
    bool bottom = false;
    for (const auto& r : found.rejected)
        if (std::abs(r.point.q[0]) < 1e-12) {
            bottom = true;
            BOOST_TEST(r.point.gap[0] == -10 * deg, boost::test_tools::tolerance(1e-12));
            BOOST_TEST(r.reason.find("outside the admissible set") != std::string::npos, r.reason);
        }
    BOOST_TEST(bottom);
}

// θ ≥ −10°: the bottom is admissible and the gap inactive there (λ = 0, interior, V'' = m g l > 0).
// On the wall V' = m g l sin(−10°) < 0: it would need λ = −0.851744311456293 < 0, refused.
BOOST_AUTO_TEST_CASE(pendulum_with_the_wall_behind_the_bottom) {
    const auto found = kkt(pendulum(-10 * deg));
    BOOST_TEST(stable_count(found) == 1);
    const u::KktEquilibrium* bottom = nullptr;
    for (const auto& e : found.equilibria)
        if (e.verdict == "stable") bottom = &e;
    BOOST_REQUIRE(bottom);
    BOOST_TEST(std::abs(bottom->point.q[0]) <= 1e-15);
    BOOST_TEST(u::name(bottom->kind) == std::string("interior"));
    BOOST_TEST(!bottom->point.active[0]);
    BOOST_TEST(bottom->point.lambda[0] == 0.0);
    BOOST_TEST(bottom->point.gap[0] == 10 * deg, boost::test_tools::tolerance(1e-12));
    BOOST_REQUIRE(bottom->curvature.size() == 1u);
    BOOST_TEST(bottom->curvature[0] == g * l, boost::test_tools::tolerance(1e-12));
    bool wall = false;
    for (const auto& r : found.rejected)
        if (r.point.active[0]) {
            wall = true;
            BOOST_TEST(r.point.q[0] == -10 * deg, boost::test_tools::tolerance(1e-12));
            BOOST_TEST(r.point.lambda[0] == -0.851744311456293, boost::test_tools::tolerance(1e-12));
            BOOST_TEST(r.reason.find("λ < 0") != std::string::npos, r.reason);
        }
    BOOST_TEST(wall);
}

// θ ≥ 0: the bottom is on the wall with λ = 0 — degenerate; V'' = m g l > 0 on the whole line, so
// stable (the tangent space of the rows pressing is everything).
BOOST_AUTO_TEST_CASE(pendulum_with_the_wall_through_the_bottom_is_degenerate) {
    const auto found = kkt(pendulum(0.0));
    BOOST_TEST(stable_count(found) == 1);
    const auto& e = found.equilibria.front();
    BOOST_TEST(std::abs(e.point.q[0]) <= 1e-15);
    BOOST_TEST(u::name(e.kind) == std::string("degenerate"));
    BOOST_TEST(e.point.active[0]);
    BOOST_TEST(std::abs(e.point.lambda[0]) <= 1e-15);
    BOOST_TEST(e.verdict == "stable");
}

// A heavy particle on a table y ≥ 0: at rest on it with λ = m g, anywhere along x (x is free).
BOOST_AUTO_TEST_CASE(particle_on_a_table) {
    const auto found = kkt(particle("m = 2.0\ng = 9.81", "m*g*y", gap("table", "y"), 0.0, 1.0));
    BOOST_REQUIRE(found.equilibria.size() == 1u);
    const auto& e = found.equilibria[0];
    BOOST_TEST(e.point.free[0]);
    BOOST_TEST(!e.point.free[1]);
    BOOST_TEST(std::abs(e.point.q[1]) <= 1e-15);
    BOOST_TEST(e.point.lambda[0] == 2.0 * g, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(u::name(e.kind) == std::string("boundary"));
    BOOST_TEST(e.verdict == "stable");
    BOOST_TEST(found.rejected.empty());
}

// A V-shaped trough y ≥ a x and y ≥ −b x (a = 1, b = 2) under gravity: only the vertex, both rows
// active. By hand, 0 = −a λ_1 + b λ_2 and m g = λ_1 + λ_2: λ_1 = m g b/(a + b), λ_2 = m g a/(a + b).
// One row alone cannot balance the horizontal part of its reaction, and in the interior nothing
// holds the weight.
BOOST_AUTO_TEST_CASE(particle_in_a_trough_rests_on_both_walls) {
    const auto found = kkt(particle("m = 2.0\ng = 9.81\na = 1.0\nb = 2.0", "m*g*y",
                                   gap("left", "y - a*x") + gap("right", "y + b*x"), 0.0, 1.0));
    BOOST_REQUIRE(found.equilibria.size() == 1u);
    const auto& e = found.equilibria[0];
    BOOST_TEST(std::abs(e.point.q[0]) <= 1e-15);
    BOOST_TEST(std::abs(e.point.q[1]) <= 1e-15);
    BOOST_TEST(e.point.active[0]);
    BOOST_TEST(e.point.active[1]);
    const double mg = 2.0 * g;
    BOOST_TEST(e.point.lambda[0] == mg * 2 / 3, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(e.point.lambda[1] == mg * 1 / 3, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(u::name(e.kind) == std::string("boundary"));
    BOOST_TEST(e.verdict == "stable");  // two independent normals in the plane: a vertex
    BOOST_TEST(e.curvature.empty());
    BOOST_REQUIRE(!e.point.exact_lambda.empty());  // solved in closed form
}

// A particle on a spring below a ceiling y ≤ h (gap h − y): hanging at y* = −m g/k (interior,
// V'' = k > 0). Pressed against the ceiling at y = h it would need λ = −(m g + k h) < 0: refused.
BOOST_AUTO_TEST_CASE(particle_below_a_ceiling) {
    const auto found = kkt(particle("m = 1.0\ng = 9.81\nk = 10.0\nh = 0.5", "m*g*y + k*y^2/2", gap("ceiling", "h - y"), 0.0, 0.0));
    BOOST_REQUIRE(found.equilibria.size() == 1u);
    const auto& e = found.equilibria[0];
    BOOST_TEST(e.point.q[1] == -0.981, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(u::name(e.kind) == std::string("interior"));
    BOOST_TEST(e.verdict == "stable");
    BOOST_REQUIRE(found.rejected.size() == 1u);
    const auto& r = found.rejected[0];
    BOOST_TEST(r.point.q[1] == 0.5, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.point.lambda[0] == -(9.81 + 10.0 * 0.5), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.reason.find("λ < 0") != std::string::npos, r.reason);

    // Without the spring nothing balances the weight: no equilibrium, the ceiling's λ = −m g refused.
    const auto hanging = kkt(particle("m = 1.0\ng = 9.81\nh = 0.5", "m*g*y", gap("ceiling", "h - y"), 0.0, 0.0));
    BOOST_TEST(hanging.equilibria.empty());
    BOOST_REQUIRE(hanging.rejected.size() == 1u);
    BOOST_TEST(hanging.rejected[0].point.lambda[0] == -9.81, boost::test_tools::tolerance(1e-12));
}

// The gap's curvature enters through the Hessian of V − λ f on the tangent space. Inside a circle
// x² + y² ≤ R² (gap R² − x² − y²): the bottom (0, −R) with λ = m g/(2R), reduced Hessian 2λ > 0,
// stable. Outside it (gap x² + y² − R²): the top (0, R) with λ = m g/(2R), reduced Hessian −2λ < 0,
// unstable — a particle on top of a smooth cylinder.
BOOST_AUTO_TEST_CASE(the_curvature_of_the_gap_decides_on_a_circle) {
    const double R = 2.0, mg = 9.81, lambda = mg / (2 * R);
    const auto inside = kkt(particle("m = 1.0\ng = 9.81\nR = 2.0", "m*g*y", gap("bowl", "R^2 - x^2 - y^2"), 0.0, 0.0));
    BOOST_REQUIRE(inside.equilibria.size() == 1u);
    const auto& bottom = inside.equilibria[0];
    BOOST_TEST(std::abs(bottom.point.q[0]) <= 1e-15);
    BOOST_TEST(bottom.point.q[1] == -R, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(bottom.point.lambda[0] == lambda, boost::test_tools::tolerance(1e-12));
    BOOST_REQUIRE(bottom.curvature.size() == 1u);
    BOOST_TEST(bottom.curvature[0] == 2 * lambda, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(bottom.verdict == "stable");

    const auto outside = kkt(particle("m = 1.0\ng = 9.81\nR = 2.0", "m*g*y", gap("drum", "x^2 + y^2 - R^2"), 0.0, 3.0));
    BOOST_REQUIRE(outside.equilibria.size() == 1u);
    const auto& top = outside.equilibria[0];
    BOOST_TEST(top.point.q[1] == R, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(top.point.lambda[0] == lambda, boost::test_tools::tolerance(1e-12));
    BOOST_REQUIRE(top.curvature.size() == 1u);
    BOOST_TEST(top.curvature[0] == -2 * lambda, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(top.verdict == "unstable");
    BOOST_REQUIRE(outside.rejected.size() == 1u);  // the bottom, which the drum would have to pull
    BOOST_TEST(outside.rejected[0].point.lambda[0] == -lambda, boost::test_tools::tolerance(1e-12));
}

// A moving wall, a velocity row and a bilateral row beside the gaps are refused at their text.
BOOST_AUTO_TEST_CASE(refusals_name_the_row) {
    const std::string base = particle("m = 1.0\ng = 9.81", "m*g*y", "", 0.0, 1.0);
    auto message = [](const std::string& toml) -> std::string {
        try {
            kkt(toml);
        } catch (const eomc::InputError& e) {
            return e.what();
        }
        return "no error";
    };
    const std::string moving = message(base + gap("floor", "y - 0.1*t"));
    BOOST_TEST(moving.find("kkt.toml:14:8: error:") != std::string::npos, moving);
    BOOST_TEST(moving.find("depends on t") != std::string::npos, moving);
    const std::string ratchet = message(base + "[[unilateral]]\nname = \"ratchet\"\nvelocity = \"y_dot\"\n");
    BOOST_TEST(ratchet.find("kkt.toml:14:") != std::string::npos, ratchet);
    BOOST_TEST(ratchet.find("velocity row") != std::string::npos, ratchet);
    const std::string bilateral =
        message(base + gap("floor", "y") + "[[constraint]]\nname = \"rail\"\nholonomic = \"x - y\"\n");
    BOOST_TEST(bilateral.find("'rail'") != std::string::npos, bilateral);
}

// `eomc equilibria` on the bundled scene: the text, JSON parsed by python3 (the wall's λ and
// verdict), LaTeX compiled by pdflatex.
BOOST_AUTO_TEST_CASE(the_command_line_prints_the_kkt_equilibria) {
    const auto dir = test_support::scratch("tests", "kkt_equilibria");
    const std::string scene = std::string(EOMC_SOURCE_DIR) + "/scenes/pendulum_leaning_wall.toml";
    const Result text = test_support::run_eomc("equilibria " + scene, dir);
    BOOST_REQUIRE(text.status == 0);
    BOOST_TEST(text.out.find("λ_α f_α = 0") != std::string::npos, text.out);
    BOOST_TEST(text.out.find("theta = 0.174532925199   (active: wall)") != std::string::npos, text.out);
    BOOST_TEST(text.out.find("boundary, stable") != std::string::npos, text.out);

    const Result json = test_support::run_eomc("equilibria " + scene + " --format json", dir);
    BOOST_REQUIRE(json.status == 0);
    test_support::write_file(dir / "e.json", json.out);
    const std::string check =
        "python3 -c \"import json,sys; d=json.load(open(sys.argv[1])); e=d['equilibria']; "
        "s=[x for x in e if x['verdict']=='stable']; assert len(s)==1, s; w=s[0]; "
        "assert w['kind']=='boundary' and w['active']==['wall'], w; "
        "assert abs(w['lambda']['wall']-0.851744311456293)<=1e-12*0.851744311456293, w; "
        "assert abs(w['q']['theta']-0.17453292519943295)<=1e-15, w; "
        "assert w['exact']['q']['theta']=='theta_w', w; "
        "assert any('outside the admissible set' in r['reason'] for r in d['rejected']), d['rejected']; "
        "assert list(d['rows'])==['wall'] and d['closed_form_complete'] is True, d\" " +
        (dir / "e.json").string() + " > " + (dir / "check.log").string() + " 2>&1";
    BOOST_TEST(std::system(check.c_str()) == 0, test_support::slurp(dir / "check.log"));

    const Result latex = test_support::run_eomc("equilibria " + scene + " --format latex", dir);
    BOOST_REQUIRE(latex.status == 0);
    test_support::write_file(dir / "e.tex", latex.out);
    const std::string compile = "cd " + dir.string() + " && pdflatex -interaction=nonstopmode -halt-on-error e.tex > e.pdflatex.log 2>&1";
    BOOST_TEST(std::system(compile.c_str()) == 0, "pdflatex failed on e.tex, see " << dir);

    // LaTeX is for the KKT equilibria only; the other equilibria still print text and JSON.
    const Result refused = test_support::run_eomc(
        "equilibria " + std::string(EOMC_SOURCE_DIR) + "/scenes/bead_on_hoop.toml --format latex", dir);
    BOOST_TEST(refused.status == 2);
    BOOST_TEST(refused.err.find("--format") != std::string::npos, refused.err);
}
