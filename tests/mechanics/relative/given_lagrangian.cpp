// A [lagrangian] scene's T given as one expression against the same system given by bodies: the
// planar chain of bench/make_pendulum_scenes.py (point masses on massless rods, angles from the
// downward vertical), written both ways. Lagrange's equations of the two must be the same
// expressions up to expansion (M and f, exactly), and the given T, whose squares are never
// expanded, must cost what the bodies cost after common-subexpression elimination (issue 19:
// within 10 %; the product rule of ε_s makes it equal).
#define BOOST_TEST_MODULE mechanics_given_lagrangian
#include <boost/test/unit_test.hpp>

#include <string>
#include <vector>

#include <fmt/format.h>
#include <ginac/ginac.h>

#include "codegen/kernel_ir.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"

#include "scenes.hpp"

using GiNaC::ex;
using eomc::model::Model;

namespace {

std::string sum(int k, const char* term) {
    std::string s;
    for (int i = 1; i <= k; ++i) s += (i > 1 ? " + " : "") + fmt::format(fmt::runtime(term), i);
    return s;
}

// The head both forms share: parameters g, m_k, l_k and the angles th_k.
std::string chain_head(int n, const std::string& name) {
    std::string s = fmt::format("[scene]\nname = \"{}\"\n\n[parameters]\ng = 9.81\n", name);
    for (int k = 1; k <= n; ++k) s += fmt::format("m{0} = 1.0\nl{0} = 1.0\n", k);
    s += "\n[coordinates]\n";
    for (int k = 1; k <= n; ++k) s += fmt::format("th{} = {{ initial = 0.1, rate = 0.0 }}\n", k);
    return s;
}

std::string potential(int n) {
    std::string V;
    for (int k = 1; k <= n; ++k) V += fmt::format("{}m{}*({})", k > 1 ? " + " : "", k, sum(k, "l{0}*cos(th{0})"));
    return "-g*(" + V + ")";
}

std::string bodies_chain(int n) {
    std::string s = chain_head(n, "chain_bodies");
    for (int k = 1; k <= n; ++k)
        s += fmt::format("\n[[body]]\nname = \"bob{0}\"\nmass = \"m{0}\"\nposition = [\"{1}\", \"-({2})\", \"0\"]\n", k,
                         sum(k, "l{0}*sin(th{0})"), sum(k, "l{0}*cos(th{0})"));
    return s + "\n[forces]\npotential = \"" + potential(n) + "\"\n";
}

// T = Σ_k m_k/2 ((Σ_{i≤k} l_i cos th_i th_i_dot)² + (Σ_{i≤k} l_i sin th_i th_i_dot)²), the squares as written.
std::string lagrangian_chain(int n) {
    std::string T;
    for (int k = 1; k <= n; ++k)
        T += fmt::format("{}m{}*(({})^2 + ({})^2)", k > 1 ? " + " : "", k, sum(k, "l{0}*cos(th{0})*th{0}_dot"),
                         sum(k, "l{0}*sin(th{0})*th{0}_dot"));
    return chain_head(n, "chain_lagrangian") + "\n[lagrangian]\nT = \"(" + T + ")/2\"\nV = \"" + potential(n) + "\"\n";
}

// The symbols of `from` by name onto those of `to` (each model makes its own).
GiNaC::exmap rename(const Model& from, const Model& to) {
    GiNaC::exmap m;
    for (std::size_t i = 0; i < from.parameters.size(); ++i) m[from.parameters[i].symbol] = to.parameters[i].symbol;
    for (std::size_t i = 0; i < from.coordinates.size(); ++i) {
        m[from.coordinates[i].q] = to.coordinates[i].q;
        m[from.coordinates[i].q_dot] = to.coordinates[i].q_dot;
        m[from.coordinates[i].q_ddot] = to.coordinates[i].q_ddot;
    }
    return m;
}

std::size_t ops_after_cse(const eomc::mechanics::Equations& eqs) {
    std::vector<ex> outputs;
    for (unsigned i = 0; i < eqs.mass_matrix.rows(); ++i)
        for (unsigned j = 0; j < eqs.mass_matrix.cols(); ++j) outputs.push_back(eqs.mass_matrix(i, j));
    outputs.insert(outputs.end(), eqs.forcing.begin(), eqs.forcing.end());
    return eomc::codegen::eliminate_common_subexpressions(outputs, "w").ops_after;
}

}  // namespace

BOOST_AUTO_TEST_CASE(given_T_and_bodies_give_the_same_equations) {
    for (const int n : {3, 4}) {
        BOOST_TEST_CONTEXT("n = " << n) {
            const Model bodies = test_support::model_of(bodies_chain(n), "bodies.toml");
            const Model given = test_support::model_of(lagrangian_chain(n), "given.toml");
            BOOST_REQUIRE(!bodies.particles.empty());
            BOOST_REQUIRE(given.particles.empty());
            const auto eb = eomc::mechanics::derive(bodies);
            const auto eg = eomc::mechanics::derive(given);
            const GiNaC::exmap to_bodies = rename(given, bodies);
            BOOST_REQUIRE_EQUAL(eg.mass_matrix.rows(), unsigned(n));
            for (unsigned i = 0; i < unsigned(n); ++i) {
                for (unsigned j = 0; j < unsigned(n); ++j) {
                    const ex d = (eb.mass_matrix(i, j) - eg.mass_matrix(i, j).subs(to_bodies)).expand();
                    BOOST_TEST(d.is_zero(), "M(" << i << "," << j << ") differs by " << d);
                    // ∂²T/∂q̇_i∂q̇_j: the given T's M is symmetric as expressions, not only in value.
                    BOOST_TEST(eg.mass_matrix(i, j).is_equal(eg.mass_matrix(j, i)));
                }
                const ex d = (eb.forcing[i] - eg.forcing[i].subs(to_bodies)).expand();
                BOOST_TEST(d.is_zero(), "f(" << i << ") differs by " << d);
            }
            // The energy integral is proven for both.
            BOOST_TEST(eg.invariants.size() == eb.invariants.size());
            const std::size_t ops_bodies = ops_after_cse(eb), ops_given = ops_after_cse(eg);
            BOOST_TEST_MESSAGE("n = " << n << ": M and f after CSE, bodies " << ops_bodies << " ops, given T "
                                      << ops_given);
            BOOST_TEST(double(ops_given) <= 1.1 * double(ops_bodies));
            BOOST_TEST(double(ops_given) >= double(ops_bodies) / 1.1);
        }
    }
}

// A T the product rule cannot simplify (velocities that are no time derivative: a rigid body's
// ½ ωᵀ I ω in Euler angles) still gives ε_s(T) = d/dt ∂T/∂q̇_s − ∂T/∂q_s: against the Euler operator
// applied the textbook way, term by term.
BOOST_AUTO_TEST_CASE(split_equals_the_euler_operator) {
    const std::string toml = R"toml(
[scene]
name = "top"
[parameters]
A = 1.3
C = 0.7
m = 2.0
g = 9.81
l = 0.4
[coordinates]
phi = { initial = 0.0, rate = 1.0 }
theta = { initial = 0.5, rate = 0.0 }
psi = { initial = 0.0, rate = 5.0 }
[lagrangian]
T = "A/2*((phi_dot*sin(theta)*sin(psi) + theta_dot*cos(psi))^2 + (phi_dot*sin(theta)*cos(psi) - theta_dot*sin(psi))^2) + C/2*(psi_dot + phi_dot*cos(theta))^2 + t*theta_dot*sin(phi)"
V = "m*g*l*cos(theta)"
)toml";
    const Model model = test_support::model_of(toml, "top.toml");
    const auto eqs = eomc::mechanics::derive(model);
    const ex& T = *model.kinetic_energy;
    for (std::size_t s = 0; s < model.coordinates.size(); ++s) {
        const auto& c = model.coordinates[s];
        ex eps = T.diff(c.q_dot).diff(model.t) - T.diff(c.q);
        for (const auto& j : model.coordinates)
            eps += T.diff(c.q_dot).diff(j.q) * j.q_dot + T.diff(c.q_dot).diff(j.q_dot) * j.q_ddot;
        const ex rhs = -model.potential.diff(c.q);
        ex lhs_minus_rhs = -eqs.forcing[s];
        for (std::size_t k = 0; k < model.coordinates.size(); ++k)
            lhs_minus_rhs += eqs.mass_matrix(unsigned(s), unsigned(k)) * model.coordinates[k].q_ddot;
        const ex d = (lhs_minus_rhs - (eps - rhs)).expand();
        BOOST_TEST(d.is_zero(), "equation " << c.name << " differs by " << d);
    }
}
