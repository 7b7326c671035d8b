// Integrals and reduction of Lagrangian scenes against known answers (Mei, ch. 5; Whittaker
// §§38, 118–119): the heavy symmetric top in Euler angles (φ, ψ cyclic, Routhian, det M =
// A²C sin²θ, gimbal lock at sin θ = 0, Jacobi's count), Kepler in polar coordinates, a damped
// oscillator (det M is not a last multiplier), the double pendulum; and the printed section in
// text, LaTeX and JSON.
#define BOOST_TEST_MODULE rigid_reduction
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>

#include <ginac/ginac.h>

#include <filesystem>
#include <fstream>
#include "mechanics/derive.hpp"
#include "mechanics/rigid/cyclic.hpp"
#include "mechanics/rigid/last_multiplier.hpp"
#include "report/derivation_printer.hpp"
#include "reduction_scenes.hpp"
#include "symbolic/differentiation.hpp"

#include "scenes.hpp"

namespace rigid = eomc::mechanics::rigid;
using eomc::model::Model;
using GiNaC::ex;

namespace {

const GiNaC::symbol& parameter(const Model& m, const std::string& name) {
    for (const auto& p : m.parameters)
        if (p.name == name) return p.symbol;
    BOOST_FAIL("no parameter " << name);
    return m.parameters.front().symbol;
}

const eomc::model::Coordinate& coordinate(const Model& m, const std::string& name) {
    for (const auto& c : m.coordinates)
        if (c.name == name) return c;
    BOOST_FAIL("no coordinate " << name);
    return m.coordinates.front();
}

double value(const ex& e, const GiNaC::exmap& at) {
    const ex v = GiNaC::evalf(e.subs(at));
    BOOST_REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

// a − b vanishes at random states (θ away from the poles), relative to |a| + |b|.
void equal_at_random_points(const ex& a, const ex& b, const Model& m, const std::vector<GiNaC::symbol>& extra = {}) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.3, 1.3);
    for (int k = 0; k < 8; ++k) {
        GiNaC::exmap at;
        for (const auto& p : m.parameters) at[p.symbol] = u(rng);
        for (const auto& c : m.coordinates) {
            at[c.q] = u(rng);
            at[c.q_dot] = u(rng) - 0.8;
            at[c.q_ddot] = u(rng) - 0.8;
        }
        for (const auto& s : extra) at[s] = u(rng) - 0.8;
        const double va = value(a, at), vb = value(b, at);
        BOOST_TEST(std::abs(va - vb) <= 1e-12 * (1 + std::abs(va) + std::abs(vb)), va << " vs " << vb);
    }
}

bool has_invariant(const eomc::mechanics::Equations& eqs, const std::string& name) {
    for (const auto& i : eqs.invariants)
        if (i.name == name) return true;
    return false;
}

std::string printed(const Model& m, const eomc::mechanics::Equations& eqs, eomc::report::DerivationFormat f) {
    std::ostringstream out;
    eomc::report::print_derivation(m, eqs, f, out);
    return out.str();
}

}  // namespace

BOOST_AUTO_TEST_CASE(top_phi_and_psi_are_cyclic_with_the_known_momenta) {
    const Model m = test_support::model_of(rigid_scenes::top());
    const auto eqs = eomc::mechanics::derive(m);
    const ex A = parameter(m, "A"), C = parameter(m, "C");
    const ex th = coordinate(m, "theta").q, phd = coordinate(m, "phi").q_dot, psd = coordinate(m, "psi").q_dot;
    const auto cyclic = rigid::cyclic_coordinates(m, eqs);
    BOOST_REQUIRE_EQUAL(cyclic.size(), 2u);
    BOOST_TEST(cyclic[0].coordinate == "phi");
    BOOST_TEST(cyclic[1].coordinate == "psi");
    BOOST_TEST(cyclic[0].proven);
    BOOST_TEST(cyclic[1].proven);
    // p_ψ = C(ψ̇ + φ̇ cos θ), p_φ = A φ̇ sin²θ + C cos θ (ψ̇ + φ̇ cos θ): exact.
    BOOST_TEST((cyclic[1].momentum - C * (psd + phd * cos(th))).expand().is_zero());
    BOOST_TEST((cyclic[0].momentum - (A * phd * pow(sin(th), 2) + C * cos(th) * (psd + phd * cos(th)))).expand().is_zero());
    // Kept among the invariants (the kernel tracks them), after the energy.
    BOOST_TEST(eqs.invariants.size() == 3u);
    BOOST_TEST(eqs.invariants[0].name == "energy");
    BOOST_TEST(has_invariant(eqs, "momentum_phi"));
    BOOST_TEST(has_invariant(eqs, "momentum_psi"));
    // θ is not cyclic: it is in T and V.
    for (const auto& c : cyclic) BOOST_TEST(c.coordinate != "theta");
}

BOOST_AUTO_TEST_CASE(top_routhian_is_the_known_one_and_gives_the_theta_equation) {
    const Model m = test_support::model_of(rigid_scenes::top());
    const auto eqs = eomc::mechanics::derive(m);
    const auto routh = rigid::routh_reduction(m, eqs, rigid::cyclic_coordinates(m, eqs));
    BOOST_REQUIRE(routh.done);
    BOOST_REQUIRE_EQUAL(routh.beta.size(), 2u);
    const ex A = parameter(m, "A"), C = parameter(m, "C"), P = parameter(m, "P"), z0 = parameter(m, "z0");
    const auto& theta = coordinate(m, "theta");
    const ex th = theta.q, thd = theta.q_dot;
    const ex b_phi = routh.beta[0], b_psi = routh.beta[1];
    // R = L − β_φ φ̇ − β_ψ ψ̇ (Whittaker §38's sign)
    //   = ½Aθ̇² − (β_φ − β_ψ cos θ)²/(2A sin²θ) − β_ψ²/(2C) − P z0 cos θ;
    // the constant −β_ψ²/(2C) is part of it with this sign convention.
    const ex expected = A * pow(thd, 2) / 2 - pow(b_phi - b_psi * cos(th), 2) / (2 * A * pow(sin(th), 2)) -
                        pow(b_psi, 2) / (2 * C) - P * z0 * cos(th);
    equal_at_random_points(routh.routhian, expected, m, routh.beta);
    // Routh's theorem: ε_θ(R) = Q_θ is the full θ equation with φ̇, ψ̇ eliminated by p = β.
    BOOST_REQUIRE_EQUAL(routh.equations.size(), 1u);
    BOOST_TEST(routh.equations[0].coordinate == "theta");
    GiNaC::exmap eliminate;
    eliminate[coordinate(m, "phi").q_dot] = routh.velocities[0];
    eliminate[coordinate(m, "psi").q_dot] = routh.velocities[1];
    const auto& eq = eqs.equations[1];
    equal_at_random_points(routh.equations[0].lhs - routh.equations[0].rhs, (eq.lhs - eq.rhs).subs(eliminate), m,
                           routh.beta);
}

BOOST_AUTO_TEST_CASE(top_last_multiplier_singular_set_and_jacobi_count) {
    const Model m = test_support::model_of(rigid_scenes::top());
    const auto eqs = eomc::mechanics::derive(m);
    const ex A = parameter(m, "A"), C = parameter(m, "C"), th = coordinate(m, "theta").q;
    const auto mult = rigid::last_multiplier(m, eqs);
    BOOST_TEST((mult.mu - A * A * C * pow(sin(th), 2)).expand().is_zero(), mult.mu);
    BOOST_TEST((mult.status == rigid::MultiplierStatus::proven), mult.reason);
    // det M = A²C sin²θ: the set sin θ = 0 (θ = 0, π), the factor squared.
    BOOST_REQUIRE_EQUAL(eqs.singular_sets.size(), 1u);
    BOOST_TEST(eqs.singular_sets[0].condition == "sin(theta) = 0");
    BOOST_TEST((eqs.singular_sets[0].indicator - sin(th)).is_zero());
    BOOST_TEST(eqs.singular_sets[0].order == 2);
    // 2n = 6 equations, autonomous; energy, p_φ, p_ψ independent: 3 of the 2n − 2 = 4 Jacobi's
    // theorem asks, so 1 missing on the full system. Routh's reduction by the 2 cyclic coordinates
    // leaves the 2 equations of (θ, θ̇), which need 2 − 2 = 0 integrals besides the multiplier (it
    // is an integrating factor there), and the energy is one more: 0 missing, integrable by
    // quadratures (then φ and ψ by quadratures of φ̇(θ), ψ̇(θ)).
    const auto count = rigid::jacobi_count(m, eqs, mult, 2);
    BOOST_TEST(count.equations == 6u);
    BOOST_TEST(count.autonomous);
    BOOST_TEST(count.integrals.size() == 3u);
    BOOST_TEST(count.needed == 4u);
    BOOST_TEST(count.missing == 1u);
    BOOST_TEST(count.cyclic == 2u);
    BOOST_TEST(count.reduced_equations == 2u);
    BOOST_TEST(count.reduced_needed == 0u);
    BOOST_TEST(count.reduced_missing == 0u);
    BOOST_TEST(count.multiplier);
    BOOST_TEST(count.integrable);
}

BOOST_AUTO_TEST_CASE(kepler_polar_theta_is_cyclic_and_det_m_is_r_squared) {
    const Model m = test_support::model_of(rigid_scenes::kepler_polar);
    const auto eqs = eomc::mechanics::derive(m);
    const ex r = coordinate(m, "r").q, thd = coordinate(m, "theta").q_dot;
    const auto cyclic = rigid::cyclic_coordinates(m, eqs);
    BOOST_REQUIRE_EQUAL(cyclic.size(), 1u);
    BOOST_TEST(cyclic[0].coordinate == "theta");
    BOOST_TEST(cyclic[0].proven);
    BOOST_TEST((cyclic[0].momentum - r * r * thd).expand().is_zero());
    BOOST_TEST(has_invariant(eqs, "momentum_theta"));
    const auto mult = rigid::last_multiplier(m, eqs);
    BOOST_TEST((mult.mu - r * r).expand().is_zero());
    BOOST_TEST((mult.status == rigid::MultiplierStatus::proven));
    BOOST_REQUIRE_EQUAL(eqs.singular_sets.size(), 1u);
    BOOST_TEST(eqs.singular_sets[0].condition == "r = 0");
    BOOST_TEST(eqs.singular_sets[0].order == 2);
    // 4 equations, energy and p_θ: the 2n − 2 = 2 Jacobi asks, nothing missing.
    const auto count = rigid::jacobi_count(m, eqs, mult, 1);
    BOOST_TEST(count.integrals.size() == 2u);
    BOOST_TEST(count.missing == 0u);
    BOOST_TEST(count.integrable);
    // The Routhian: R = ṙ²/2 − β²/(2r²) + μ/r.
    const auto routh = rigid::routh_reduction(m, eqs, cyclic);
    BOOST_REQUIRE(routh.done);
    const ex mu = parameter(m, "mu"), rd = coordinate(m, "r").q_dot, b = routh.beta[0];
    equal_at_random_points(routh.routhian, rd * rd / 2 - b * b / (2 * r * r) + mu / r, m, routh.beta);
}

BOOST_AUTO_TEST_CASE(damped_oscillator_det_m_is_not_a_last_multiplier) {
    const Model m = test_support::model_of(rigid_scenes::damped);
    const auto eqs = eomc::mechanics::derive(m);
    BOOST_TEST(rigid::cyclic_coordinates(m, eqs).empty());
    BOOST_TEST(eqs.singular_sets.empty());
    const auto mult = rigid::last_multiplier(m, eqs);
    // μ = m, F = (ẋ, −(k x + c ẋ)/m): div(μF) = −c ≠ 0.
    BOOST_TEST((mult.mu - parameter(m, "m")).is_zero());
    BOOST_TEST((mult.status == rigid::MultiplierStatus::not_multiplier), mult.reason);
    BOOST_TEST((mult.divergence.expand() + parameter(m, "c")).is_zero(), mult.divergence);
    const auto count = rigid::jacobi_count(m, eqs, mult, 0);
    BOOST_TEST(!count.multiplier);
    BOOST_TEST(!count.integrable);
    const std::string text = printed(m, eqs, eomc::report::DerivationFormat::text);
    BOOST_TEST(text.find("not a last multiplier") != std::string::npos, text);
    BOOST_TEST(text.find("a last multiplier (proven)") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_free_coordinate_with_a_force_is_not_cyclic) {
    // x is absent from L = m ẋ²/2, but Q_x = −c ẋ ≠ 0: p_x = m ẋ decays, nothing is claimed.
    std::string scene = rigid_scenes::damped;
    scene.replace(scene.find("V = \"k*x^2/2\""), 13, "V = \"0\"");
    const Model m = test_support::model_of(scene);
    const auto eqs = eomc::mechanics::derive(m);
    BOOST_TEST(rigid::cyclic_coordinates(m, eqs).empty());
    BOOST_TEST(!has_invariant(eqs, "momentum_x"));
}

BOOST_AUTO_TEST_CASE(double_pendulum_has_no_cyclic_coordinate_and_det_m_is_a_multiplier) {
    const Model m = test_support::bundled_model("double_pendulum");
    const auto eqs = eomc::mechanics::derive(m);
    BOOST_TEST(rigid::cyclic_coordinates(m, eqs).empty());
    BOOST_TEST(eqs.singular_sets.empty());  // det M = l1²l2²m2(m1 + m2 sin²(θ1 − θ2)) > 0
    const auto mult = rigid::last_multiplier(m, eqs);
    BOOST_TEST((mult.status == rigid::MultiplierStatus::proven), mult.reason);
    const auto count = rigid::jacobi_count(m, eqs, mult, 0);
    BOOST_TEST(count.integrals.size() == 1u);  // the energy
    BOOST_TEST(count.missing == 1u);
    BOOST_TEST(!count.integrable);
    const auto routh = rigid::routh_reduction(m, eqs, {});
    BOOST_TEST(!routh.done);
}

BOOST_AUTO_TEST_CASE(the_kernel_carries_singular_sets_only_where_there_are_some) {
    const auto top = test_support::kernel_of(rigid_scenes::top());
    BOOST_TEST(top.header.find("singular_set_names{ \"sin(theta) = 0\" }") != std::string::npos);
    BOOST_TEST(top.header.find("singular_set_orders{ 2 }") != std::string::npos);
    BOOST_TEST(top.header.find("\"momentum_phi\", \"momentum_psi\"") != std::string::npos);
    const auto pendulum = test_support::kernel_of(test_support::bundled_scene("double_pendulum"));
    BOOST_TEST(pendulum.header.find("singular_set") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_derivation_prints_the_section_in_every_format) {
    const Model m = test_support::model_of(rigid_scenes::top());
    const auto eqs = eomc::mechanics::derive(m);
    const std::string text = printed(m, eqs, eomc::report::DerivationFormat::text);
    for (const char* s : {"Integrals and reduction", "Cyclic coordinates", "p_phi = ∂L/∂phi_dot", "Routh's reduction",
                          "R = ", "reduced equations", "Jacobi's last multiplier μ = det M = ",
                          "a last multiplier (proven)", "Jacobi's count: 6 first-order equations",
                          "integrable by quadratures", "sin(theta) = 0"})
        BOOST_TEST(text.find(s) != std::string::npos, s);
    const std::string latex = printed(m, eqs, eomc::report::DerivationFormat::latex);
    BOOST_TEST(latex.find("\\subsection*{Integrals and reduction}") != std::string::npos);
    BOOST_TEST(latex.find("\\beta_{phi}") != std::string::npos);
    BOOST_TEST(latex.rfind("\\end{document}") > latex.find("Integrals and reduction"));
    BOOST_TEST(latex.find("momentum_") == std::string::npos);  // the underscore escaped wherever names appear
    const std::string json = printed(m, eqs, eomc::report::DerivationFormat::json);
    for (const char* s : {"\"reduction\": {\"cyclic\": [", "\"routhian\": {\"R\": ", "\"last_multiplier\": {\"mu\": ",
                          "\"status\": \"proven\"", "\"jacobi_count\": {\"equations\": 6", "\"missing\": 1",
                          "\"reduced_missing\": 0", "\"integrable\": true",
                          "\"singular_sets\": [{\"condition\": \"sin(theta) = 0\""})
        BOOST_TEST(json.find(s) != std::string::npos, s);
    const std::filesystem::path dir = std::filesystem::path(EOMC_BINARY_DIR) / "rigid" / "json";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "d.json") << json;
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "d.json").string() + " > /dev/null").c_str()) == 0);
    // A scene with constraint rows: the multiplier is not examined, and the JSON still parses.
    const Model sleigh = test_support::bundled_model("chaplygin_sleigh");
    const auto sleigh_eqs = eomc::mechanics::derive(sleigh);
    std::ofstream(dir / "s.json") << printed(sleigh, sleigh_eqs, eomc::report::DerivationFormat::json);
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "s.json").string() + " > /dev/null").c_str()) == 0);
}

// Jacobi's last multiplier over every bundled scene given by its energies (Whittaker §119): det M
// is one exactly when no force outside L depends on the velocities. Scenes with constraint rows
// (bilateral or unilateral) or a free carrier have another first-order form (not examined); a
// damped particle's −c v and the damped hoop's −c θ̇ are the velocity-dependent forces among them.
BOOST_AUTO_TEST_CASE(det_m_is_a_last_multiplier_of_every_bundled_lagrangian_scene) {
    namespace fs = std::filesystem;
    std::size_t proven = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(EOMC_SOURCE_DIR) / "scenes")) {
        const auto model = test_support::bundled_model(entry.path().stem().string());
        if (model.kind() != eomc::model::ModelKind::energies) continue;
        const auto eqs = eomc::mechanics::derive(model);
        const auto mu = eomc::mechanics::rigid::last_multiplier(model, eqs);
        BOOST_TEST_CONTEXT(model.name) {
            using Status = eomc::mechanics::rigid::MultiplierStatus;
            // Unilateral rows make the flow discontinuous (impacts): not examined either.
            if (!model.constraints.empty() || !model.unilateral.empty() || model.free_carrier()) {
                BOOST_TEST((mu.status == Status::not_applicable));
            } else if (model.name == "damped_particle" || model.name == "bead_on_hoop_damped") {
                BOOST_TEST((mu.status == Status::not_multiplier));
            } else {
                BOOST_TEST((mu.status == Status::proven), mu.reason);
                ++proven;
            }
        }
    }
    BOOST_TEST(proven >= 10u);
}
