// The seed's example of a free carrier (Mei §1.1, Fig. 1-1; FORMULAS §1): a disc M, r with a
// tube along x' through o and a ball m at q i', v_o = v0 j', ω = w j'. The derivation must
// give exactly the checked forms
//   (1.1.36)  m(q̈ − q w²) = V1,   (M + m) v̇0 = V2,   −m(q ẇ + 2 q̇ w) = V3,
//   (1.1.38)  0 = m1,   (½ M r² + m q²) ẇ + 2 m q q̇ w = m2,   m q v̇0 = m3,
// where the held components' V1, V3, m1, m3 are the reactions R_1, R_3, N_1, N_3 and V2, m2 the
// applied loads. Compared as polynomials (expand().is_zero()): exact, no tolerance.
#define BOOST_TEST_MODULE mechanics_free_carrier
#include <boost/test/unit_test.hpp>

#include <ginac/ginac.h>

#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

using GiNaC::ex;

namespace {

const char* const seed = R"toml(
[scene]
name = "seed_free_carrier"
[parameters]
M = 2.0
m = 0.5
r = 1.0
V2 = 0.3
m2 = 0.1
[coordinates]
q = { initial = 0.1, rate = 0.0 }
[carrier]
motion = "free"
mass = "M"
inertia = ["M*r^2/4", "M*r^2/2", "M*r^2/4"]
pole_velocity = ["0", "v0", "0"]
angular_velocity = ["0", "w", "0"]
[carrier.initial]
v0 = 0.0
w = 1.0
[[body]]
name = "ball"
mass = "m"
position = ["q", "0", "0"]
[forces]
resultant = ["0", "V2", "0"]
moment = ["0", "m2", "0"]
)toml";

eomc::model::Model model_of(const std::string& toml) {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, "seed.toml"));
}

ex symbol_named(const eomc::model::Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    for (const auto& v : model.quasi_velocities) {
        if (v.name == name) return v.symbol;
        if (v.name + "_dot" == name) return v.rate;
    }
    for (const auto& c : model.coordinates) {
        if (c.name == name) return c.q;
        if (c.name + "_dot" == name) return c.q_dot;
        if (c.name + "_ddot" == name) return c.q_ddot;
    }
    throw std::runtime_error("no symbol " + name);
}

}  // namespace

BOOST_AUTO_TEST_CASE(seed_example_comes_out_as_1_1_36_and_1_1_38) {
    const auto model = model_of(seed);
    const auto eqs = eomc::mechanics::derive(model);
    auto s = [&](const char* name) { return symbol_named(model, name); };
    const ex M = s("M"), m = s("m"), r = s("r"), q = s("q"), q_dot = s("q_dot"), q_ddot = s("q_ddot"), w = s("w"),
             w_dot = s("w_dot"), v0_dot = s("v0_dot");
    const ex lhs[6] = {m * (q_ddot - q * w * w), (M + m) * v0_dot, -m * (q * w_dot + 2 * q_dot * w),
                       0, (M * r * r / 2 + m * q * q) * w_dot + 2 * m * q * q_dot * w, m * q * v0_dot};
    const char* names[6] = {"force_1", "force_2", "force_3", "moment_1", "moment_2", "moment_3"};
    BOOST_REQUIRE_EQUAL(eqs.carrier_equations.size(), 6u);
    for (int i = 0; i < 6; ++i) {
        const auto& c = eqs.carrier_equations[std::size_t(i)];
        BOOST_TEST(c.name == names[i]);
        BOOST_TEST_INFO(c.name << ": derived " << c.lhs << ", expected " << lhs[i]);
        BOOST_TEST((c.lhs - lhs[i]).expand().is_zero());
    }
    // Held: v_o,1 v_o,3 ω_1 ω_3 (reactions); unknown: v0 from force_2, w from moment_2.
    BOOST_TEST(eqs.carrier_equations[0].held);
    BOOST_TEST(eqs.carrier_equations[1].quasi_velocity == "v0");
    BOOST_TEST((eqs.carrier_equations[1].applied - s("V2")).is_zero());
    BOOST_TEST(eqs.carrier_equations[4].quasi_velocity == "w");
    BOOST_TEST((eqs.carrier_equations[4].applied - s("m2")).is_zero());
    BOOST_TEST(eqs.carrier_equations[3].reaction.get_name() == "N1");
    // Lagrange's equation in q is (1.1.36)'s first line with the smooth tube's Q_q = 0.
    BOOST_TEST((eqs.equations[0].lhs - lhs[0]).expand().is_zero());
    // M over u = (q̇, v0, w) and f follow: M = diag(m, M + m, ½Mr² + mq²).
    BOOST_REQUIRE_EQUAL(eqs.mass_matrix.rows(), 3u);
    const ex diagonal[3] = {m, M + m, M * r * r / 2 + m * q * q};
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j)
            BOOST_TEST((eqs.mass_matrix(i, j) - (i == j ? diagonal[i] : ex(0))).expand().is_zero());
    BOOST_TEST((eqs.forcing[2] - (s("m2") - 2 * m * q * q_dot * w)).expand().is_zero());
    // The loads do work: no energy integral may be claimed.
    BOOST_TEST(eqs.invariants.empty());
}

BOOST_AUTO_TEST_CASE(free_carrier_input_errors_point_at_the_component) {
    std::string bad = seed;
    bad.replace(bad.find(R"(["0", "w", "0"])"), 15, R"(["0", "2*w", "0"])");
    try {
        model_of(bad);
        BOOST_FAIL("expected an error");
    } catch (const eomc::InputError& e) {
        const std::string what = e.what();
        BOOST_TEST(what.find("seed.toml:17:") != std::string::npos, what);
        BOOST_TEST(what.find("new name") != std::string::npos, what);
    }
    std::string typo = seed;
    typo.replace(typo.find("w = 1.0"), 7, "ww = 1.0");
    try {
        model_of(typo);
        BOOST_FAIL("expected an error");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("did you mean 'w'") != std::string::npos, e.what());
    }
}
