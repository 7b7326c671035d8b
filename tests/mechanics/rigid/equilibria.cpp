// Permanent rotations of the heavy rigid body (Staude 1894; Mei, ch. 5) and their stability,
// against closed forms: the Lagrange top sleeping on its axis (Maievskii's criterion
// C² r0² > 4 A P z0 and the eigenvalues ±i[(2A − C) r0 ± √(C² r0² − 4 A P z0)]/(2A)), a generic
// body's rotation about a vertical on Staude's cone (the field vanishing there exactly), Euler's
// body (the middle axis unstable), and `eomc equilibria` on a rigid scene (text, JSON) and on a
// Lagrangian one (unchanged).
#define BOOST_TEST_MODULE rigid_equilibria
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "mechanics/rigid/equilibria.hpp"
#include "mechanics/rigid/euler_poisson.hpp"
#include "model/model.hpp"

#include "command.hpp"
#include "scenes.hpp"

using namespace eomc;
namespace rigid = eomc::mechanics::rigid;
using GiNaC::ex;

namespace {

const std::string lagrange_scene = R"toml([scene]
name = "lagrange_top"
[parameters]
A = 1.5
C = 0.6
P = 2.0
z0 = 0.25
[rigid_body]
inertia = ["A", "A", "C"]
center = ["0", "0", "z0"]
weight = "P"
[rigid_body.initial]
omega = [0.0, 0.0, 3.2]
vertical = [0.0, 0.0, 1.0]
[simulate]
t_end = 1.0
)toml";

// A = 1, B = 2, C = 3, r_c = (1, 1, 1), P = 1: Staude's cone is γ2γ3 − 2γ3γ1 + γ1γ2 = 0, which
// holds γ = (−1, −3, 3)/√19 (γ × Iγ = (−9, 6, 3)/19, γ × r_c = (2/3)(−9, 6, 3)/√19), where
// Ω² = P (γ × r_c)·(γ × Iγ)/|γ × Iγ|² = 2√19/3.
const std::string generic_scene = R"toml([scene]
name = "generic_body"
[parameters]
A = 1.0
B = 2.0
C = 3.0
P = 1.0
[rigid_body]
inertia = ["A", "B", "C"]
center = ["1", "1", "1"]
weight = "P"
[rigid_body.initial]
omega = [0.0, 0.0, 1.0]
vertical = [0.0, 0.0, 1.0]
)toml";

GiNaC::symbol parameter(const model::Model& m, const std::string& name) {
    for (const auto& p : m.parameters)
        if (p.name == name) return p.symbol;
    throw std::runtime_error("no parameter " + name);
}

double at_defaults(const model::Model& m, const ex& e) {
    return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(m.parameter_defaults()))).to_double();
}

// The frequencies |Im λ| > 0 on the leaf, descending, one per ± pair.
std::vector<double> frequencies(const rigid::PermanentRotation& r) {
    std::vector<double> f;
    for (const auto& l : r.reduced)
        if (l.imag() > 0) f.push_back(l.imag());
    std::sort(f.rbegin(), f.rend());
    return f;
}

}  // namespace

BOOST_AUTO_TEST_CASE(lagrange_criterion_is_derived_and_is_maievskiis) {
    const model::Model m = test_support::model_of(lagrange_scene);
    const auto c = rigid::sleeping_criterion(m, 1);
    BOOST_REQUIRE(c);
    const ex A = parameter(m, "A"), C = parameter(m, "C"), P = parameter(m, "P"), z0 = parameter(m, "z0");
    const ex r0 = c->spin;
    // The criterion, as GiNaC left it, is Maievskii's (up to nothing: same sign, same scale).
    BOOST_TEST(GiNaC::normal(c->criterion - (C * C * r0 * r0 - 4 * A * P * z0)).is_zero(),
               "criterion " << c->criterion);
    BOOST_REQUIRE(c->critical_spin);
    BOOST_TEST(GiNaC::normal(GiNaC::pow(*c->critical_spin, 2) - 4 * A * P * z0 / (C * C)).is_zero());
    BOOST_TEST(at_defaults(m, *c->critical_spin) == 2.88675134594813, boost::test_tools::tolerance(1e-13));
    // The closed-form eigenvalues are roots of the derived quartic: λ = i μ, μ = [(2A − C) r0 ± √D]/(2A).
    const ex D = C * C * r0 * r0 - 4 * A * P * z0;
    for (int s : {1, -1}) {
        const ex mu = ((2 * A - C) * r0 + s * GiNaC::sqrt(D)) / (2 * A);
        const ex value = c->quartic.subs(c->lambda == GiNaC::I * mu);
        GiNaC::exmap at = m.parameter_defaults();
        at[c->spin] = GiNaC::numeric(32, 10);
        BOOST_TEST(std::abs(GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(value.subs(at))).to_double()) < 1e-12);
    }
    // Hanging (γ = −e3): C² r0² + 4 A P z0 > 0 at every spin, so no critical spin.
    const auto hanging = rigid::sleeping_criterion(m, -1);
    BOOST_REQUIRE(hanging);
    BOOST_TEST(GiNaC::normal(hanging->criterion - (C * C * hanging->spin * hanging->spin + 4 * A * P * z0)).is_zero());
    BOOST_TEST(!hanging->critical_spin);
}

BOOST_AUTO_TEST_CASE(sleeping_lagrange_top_eigenvalues) {
    const model::Model m = test_support::model_of(lagrange_scene);
    // r0 = 3.2 > 2.88675…: stable, λ = ±2.83616420236 i, ±2.28383579764 i, and two zeros.
    const auto fast = rigid::linearise_rotation(m, {0, 0, 1}, 3.2);
    BOOST_TEST(fast.verdict == "spectrally stable");
    const auto f = frequencies(fast);
    BOOST_REQUIRE(f.size() == 2u);
    const double A = 1.5, C = 0.6, P = 2, z0 = 0.25, r0 = 3.2, root = std::sqrt(C * C * r0 * r0 - 4 * A * P * z0);
    BOOST_TEST(f[0] == ((2 * A - C) * r0 + root) / (2 * A), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(f[1] == ((2 * A - C) * r0 - root) / (2 * A), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(f[0] == 2.83616420236, boost::test_tools::tolerance(1e-11));
    BOOST_TEST(f[1] == 2.28383579764, boost::test_tools::tolerance(1e-11));
    for (const auto& l : fast.reduced) BOOST_TEST(std::abs(l.real()) < 1e-12);
    BOOST_REQUIRE(fast.eigenvalues.size() == 6u);
    int zeros = 0;
    for (const auto& l : fast.eigenvalues) zeros += std::abs(l) < 1e-12;
    BOOST_TEST(zeros == 2);
    // r0 = 2.5 below it: λ = ±0.288675134595 ± 2 i.
    const auto slow = rigid::linearise_rotation(m, {0, 0, 1}, 2.5);
    BOOST_TEST(slow.verdict == "unstable");
    for (const auto& l : slow.reduced) {
        BOOST_TEST(std::abs(l.real()) == 0.288675134595, boost::test_tools::tolerance(1e-11));
        BOOST_TEST(std::abs(l.imag()) == 2.0, boost::test_tools::tolerance(1e-12));
    }
}

BOOST_AUTO_TEST_CASE(scene_report_for_the_lagrange_top) {
    const model::Model m = test_support::model_of(lagrange_scene);
    const auto found = rigid::rigid_equilibria(m);
    BOOST_TEST(found.spin == 3.2);  // ω0·γ0
    BOOST_TEST(found.cone.is_zero());  // A = B, r_c on the axis: every vertical
    BOOST_REQUIRE(found.rotations.size() == 2u);  // ±e3, any spin
    BOOST_TEST(found.rotations[0].label == "+e3");
    BOOST_TEST(found.rotations[0].any_spin);
    BOOST_TEST(found.rotations[0].verdict == "spectrally stable");
    BOOST_REQUIRE(found.initial);
    BOOST_TEST(found.initial->spin == 3.2);
    BOOST_TEST(found.lagrange.size() == 2u);
    const auto slow = rigid::rigid_equilibria(m, 2.5);
    BOOST_TEST(slow.rotations[0].verdict == "unstable");
    BOOST_TEST(slow.rotations[1].verdict == "spectrally stable");  // hanging: stable at any spin
}

BOOST_AUTO_TEST_CASE(staude_cone_rotation_of_a_generic_body_keeps_the_field_at_rest) {
    const model::Model m = test_support::model_of(generic_scene);
    const auto found = rigid::rigid_equilibria(m);
    const model::RigidBody& body = *m.rigid;
    const ex s19 = GiNaC::sqrt(ex(19));
    const ex g[3] = {-1 / s19, -3 / s19, 3 / s19};
    // The parameters as exact integers (the defaults are doubles).
    GiNaC::exmap on_cone{{parameter(m, "A"), 1}, {parameter(m, "B"), 2}, {parameter(m, "C"), 3}, {parameter(m, "P"), 1}};
    for (int i = 0; i < 3; ++i) on_cone[body.gamma[i]] = g[i];
    // On the printed cone, exactly.
    BOOST_TEST(GiNaC::normal(found.cone.subs(on_cone)).is_zero(), "cone " << found.cone);
    // Ω² from the library's formula, the symbolic one and by hand: 2√19/3 > 0.
    const std::array<double, 3> gd{-1 / std::sqrt(19.0), -3 / std::sqrt(19.0), 3 / std::sqrt(19.0)};
    const double W2 = rigid::staude_spin_squared(m, gd);
    BOOST_TEST(W2 > 0);
    BOOST_TEST(W2 == 2 * std::sqrt(19.0) / 3, boost::test_tools::tolerance(1e-14));
    const ex W2_exact = GiNaC::normal(found.spin_on_cone.subs(on_cone));
    BOOST_TEST(GiNaC::normal(W2_exact - 2 * s19 / 3).is_zero(), "Ω² " << W2_exact);
    // The Euler–Poisson field vanishes there exactly: I ω̇ = 0 and γ̇ = 0 at ω = Ω γ.
    const rigid::EulerPoisson s = rigid::euler_poisson(body);
    GiNaC::exmap state = on_cone;
    const ex W = GiNaC::sqrt(W2_exact);
    for (int i = 0; i < 3; ++i) state[body.omega[i]] = W * g[i];
    for (int i = 0; i < 3; ++i) {
        BOOST_TEST(GiNaC::normal(s.forcing[i].subs(state).expand()).is_zero(), "I ω̇ " << i);
        BOOST_TEST(GiNaC::normal(s.gamma_rate[i].subs(state).expand()).is_zero(), "γ̇ " << i);
    }
    BOOST_TEST(rigid::rotation_residual(m, gd, std::sqrt(W2)) < 1e-14);
    // Its spectrum on the leaf: a Hamiltonian 4×4, so symmetric about both axes.
    const auto r = rigid::linearise_rotation(m, gd, std::sqrt(W2));
    BOOST_TEST(r.reduced.size() == 4u);
    BOOST_TEST((r.verdict == "spectrally stable" || r.verdict == "unstable"));
    std::complex<double> sum = 0;
    for (const auto& l : r.reduced) sum += l;
    BOOST_TEST(std::abs(sum) < 1e-12);
    // The other direction, γ = (1, 3, −3)/√19, gives Ω² < 0: no rotation.
    BOOST_TEST(rigid::staude_spin_squared(m, {-gd[0], -gd[1], -gd[2]}) == -W2, boost::test_tools::tolerance(1e-14));
    // r_c on no principal axis: no sleeping rotations; the initial state is not one.
    BOOST_TEST(found.rotations.empty());
    BOOST_TEST(!found.initial);
}

BOOST_AUTO_TEST_CASE(euler_body_middle_axis_is_unstable) {
    const model::Model m = test_support::model_of(R"toml([scene]
name = "euler_body"
[parameters]
A = 1.0
B = 2.0
C = 3.0
[rigid_body]
inertia = ["A", "B", "C"]
center = ["0", "0", "0"]
weight = "1"
[rigid_body.initial]
omega = [0.0, 1.0, 0.0]
vertical = [0.0, 1.0, 0.0]
)toml");
    const auto found = rigid::rigid_equilibria(m);
    BOOST_REQUIRE(found.rotations.size() == 6u);
    for (const auto& r : found.rotations)
        BOOST_TEST(r.verdict == ((r.label == "+e2" || r.label == "−e2") ? "unstable" : "spectrally stable"), r.label);
    BOOST_REQUIRE(found.initial);
    BOOST_TEST(found.initial->verdict == "unstable");
    // Growth rate Ω √((B − A)(C − B)/(A C)) about the middle axis.
    double growth = 0;
    for (const auto& l : found.initial->reduced) growth = std::max(growth, l.real());
    BOOST_TEST(growth == std::sqrt(1.0 * 1.0 / 3.0), boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(cli_text_and_json_for_a_rigid_scene) {
    const auto dir = test_support::scratch("rigid_equilibria", "cli");
    const auto scene = test_support::write_scene(dir, lagrange_scene);
    const auto text = test_support::run_eomc("equilibria " + scene.string(), dir);
    BOOST_TEST(text.status == 0, text.err);
    BOOST_TEST(text.out.find("Staude's cone") != std::string::npos);
    BOOST_TEST(text.out.find("spectrally stable iff -4*P*z0*A+r0^2*C^2 > 0") != std::string::npos, text.out);
    BOOST_TEST(text.out.find("critical spin |r0| = 2*sqrt(P*z0*A)*C^(-1)") != std::string::npos, text.out);
    BOOST_TEST(text.out.find("(0+2.83616420236i)") != std::string::npos, text.out);
    const auto slow = test_support::run_eomc("equilibria " + scene.string() + " --spin 2.5", dir);
    BOOST_TEST(slow.status == 0, slow.err);
    BOOST_TEST(slow.out.find("Ω = 2.5 (any Ω") != std::string::npos);
    BOOST_TEST(slow.out.find("unstable") != std::string::npos);
    const auto json = test_support::run_eomc("equilibria " + scene.string() + " --format json", dir);
    BOOST_TEST(json.status == 0, json.err);
    BOOST_TEST(json.out.find("\"rigid\": true") != std::string::npos);
    test_support::write_file(dir / "out.json", json.out);
    const int rc = std::system(("python3 -m json.tool " + (dir / "out.json").string() + " > /dev/null").c_str());
    BOOST_TEST(rc == 0, json.out);
}

BOOST_AUTO_TEST_CASE(cli_lagrangian_scene_unchanged) {
    const auto dir = test_support::scratch("rigid_equilibria", "lagrangian");
    const auto scene = test_support::write_scene(dir, R"toml([scene]
name = "hoop"
[parameters]
m = 0.1
R = 0.5
g = 9.81
omega = 2.0
[coordinates]
theta = {}
[carrier]
angular_velocity = ["0", "0", "omega"]
[[body]]
name = "bead"
mass = "m"
position = ["R*sin(theta)", "0", "-R*cos(theta)"]
[forces]
potential = "-m*g*R*cos(theta)"
)toml");
    const auto text = test_support::run_eomc("equilibria " + scene.string(), dir);
    BOOST_TEST(text.status == 0, text.err);
    BOOST_TEST(text.out.find("relative equilibri") != std::string::npos, text.out);
    BOOST_TEST(text.out.find("Staude") == std::string::npos);
    const auto json = test_support::run_eomc("equilibria " + scene.string() + " --format json", dir);
    BOOST_TEST(json.out.rfind("{\"equilibria\": [", 0) == 0u, json.out);
}
