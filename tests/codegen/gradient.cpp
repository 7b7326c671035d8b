// symbolic::Gradient (the Jacobian's one forward-mode pass, codegen/lower.cpp) against
// symbolic::derivative taken entry by entry, the way lower.cpp formed ∂ẋ/∂x before: on the very
// rows lower.cpp differentiates (the explicit rates and f_i − Σ_k M_ik u̇_k), for bundled scenes
// (a rigid body in two formulations, a constrained pendulum, a carrier scene) and a 6-link
// planar chain, and on hand-written expressions that reach every rule (sum, product, numeric
// and symbolic powers, the scene language's functions, Kepler's E, GiNaC's diff).
//
// Each entry must be the same expression (GiNaC::ex::is_equal): Gradient builds entry j from the
// same operands in the same order as derivative(e, x_j). Failing that, the difference must
// expand to zero (GiNaC check/exam_*.cpp): a reordering would be acceptable, a different value
// never.
#define BOOST_TEST_MODULE codegen_gradient
#include <boost/test/unit_test.hpp>

#include <string>
#include <vector>

#include <fmt/format.h>

#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "model/kepler_function.hpp"
#include "scene/scene.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/gradient.hpp"

#include "scenes.hpp"

using GiNaC::ex;

namespace {

// Every entry of one Gradient over `rows` against derivative(row, x_j); returns the entries compared.
std::size_t check_against_derivative(const std::vector<ex>& rows, const std::vector<GiNaC::symbol>& variables,
                                     const std::string& what) {
    eomc::symbolic::Gradient gradient(variables);
    std::size_t compared = 0, nonzero = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::vector<ex> g = gradient(rows[i]);
        BOOST_TEST_REQUIRE(g.size() == variables.size());
        for (std::size_t j = 0; j < variables.size(); ++j) {
            const ex expected = eomc::symbolic::derivative(rows[i], variables[j]);
            const bool same = g[j].is_equal(expected) || (g[j] - expected).expand().is_zero();
            BOOST_TEST_INFO(what << ": d(row " << i << ")/d" << variables[j] << ": gradient " << g[j]
                                 << ", derivative " << expected);
            BOOST_TEST(same);
            ++compared;
            nonzero += expected.is_zero() ? 0 : 1;
        }
    }
    // The scenes' Jacobians are not all zero: the comparison has something to compare.
    BOOST_TEST(nonzero > 0u, what << ": every derivative is zero");
    return compared;
}

// The rows lower.cpp differentiates for a first-order form: the explicit rates, then the
// residuals f_i − Σ_k M_ik u̇_k with u̇ held as symbols; with constraint rows, their position,
// velocity and bias too (differentiated nowhere today, but expressions of the same kind).
std::vector<ex> lowered_rows(const eomc::mechanics::FirstOrderForm& form) {
    std::vector<ex> rows;
    for (const auto& [index, rate] : form.explicit_rates) rows.push_back(rate);
    for (std::size_t i = 0; i < form.n_velocities(); ++i) {
        ex residual = form.forcing[i];
        for (std::size_t k = 0; k < form.n_velocities(); ++k)
            residual -= form.mass_matrix(unsigned(i), unsigned(k)) * form.velocity_rates[k].symbol;
        rows.push_back(residual);
    }
    for (const auto& row : form.constraints) rows.insert(rows.end(), {row.position, row.velocity, row.bias});
    return rows;
}

std::vector<GiNaC::symbol> state_symbols(const eomc::mechanics::FirstOrderForm& form) {
    std::vector<GiNaC::symbol> x;
    for (const auto& s : form.state) x.push_back(GiNaC::ex_to<GiNaC::symbol>(s.symbol));
    return x;
}

void check_model(const eomc::model::Model& model, const std::string& what) {
    const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    const std::size_t compared = check_against_derivative(lowered_rows(form), state_symbols(form), what);
    BOOST_TEST_MESSAGE(what << ": " << compared << " entries agree");
}

// The n-link planar pendulum of bench/make_pendulum_scenes.py.
std::string chain_scene(int n) {
    std::string s = "[scene]\nname = \"chain\"\n[parameters]\ng = 9.81\n";
    for (int k = 1; k <= n; ++k) s += fmt::format("m{0} = 1.0\nl{0} = 1.0\n", k);
    s += "[coordinates]\n";
    for (int k = 1; k <= n; ++k) s += fmt::format("th{} = {{ initial = 0.1, rate = 0.0 }}\n", k);
    std::string x, y, potential;
    for (int k = 1; k <= n; ++k) {
        const std::string K = std::to_string(k);
        x += (k > 1 ? " + " : "") + ("l" + K + "*sin(th" + K + ")");
        y += (k > 1 ? " + " : "") + ("l" + K + "*cos(th" + K + ")");
        s += "[[body]]\nname = \"bob" + K + "\"\nmass = \"m" + K + "\"\nposition = [\"" + x + "\", \"-(" + y +
             ")\", \"0\"]\n";
        potential += (k > 1 ? " + " : "") + ("m" + K + "*(" + y + ")");
    }
    return s + "[forces]\npotential = \"-g*(" + potential + ")\"\n";
}

}  // namespace

BOOST_AUTO_TEST_CASE(rigid_body_euler_poisson) {
    check_model(test_support::bundled_model("heavy_gyrostat"), "heavy_gyrostat (euler_poisson)");
}

BOOST_AUTO_TEST_CASE(rigid_body_euler_angles) {
    auto scene = eomc::scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) + "/scenes/kovalevskaya_top.toml");
    eomc::scene::set_rigid_formulation(scene, "euler_angles", eomc::SourcePos{"test"});
    check_model(eomc::model::build_model(scene), "kovalevskaya_top (euler_angles)");
}

BOOST_AUTO_TEST_CASE(constrained_pendulum) {
    const auto model = test_support::bundled_model("pendulum_cartesian");
    const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    BOOST_TEST_REQUIRE(!form.constraints.empty());
    check_against_derivative(lowered_rows(form), state_symbols(form), "pendulum_cartesian");
}

BOOST_AUTO_TEST_CASE(carrier_scene) { check_model(test_support::bundled_model("foucault_pendulum"), "foucault"); }

BOOST_AUTO_TEST_CASE(six_link_chain) {
    const auto model = test_support::model_of(chain_scene(6));
    const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    BOOST_TEST_REQUIRE(form.state.size() == 12u);
    BOOST_TEST(check_against_derivative(lowered_rows(form), state_symbols(form), "6-link chain") == 12u * 12u);  // 6 rates, 6 residuals
}

// One expression per rule, and the symbols' order kept in the result.
BOOST_AUTO_TEST_CASE(every_rule) {
    const GiNaC::symbol x("x"), y("y"), z("z"), a("a");
    const std::vector<ex> rows{
        x * y * z + a * x,                                  // sum and product
        GiNaC::pow(x + y, 3) + GiNaC::pow(y, -1) * z,       // numeric powers
        GiNaC::pow(x, y) + GiNaC::pow(a, z),                // symbolic powers: GiNaC's diff
        GiNaC::sin(x * y) * GiNaC::cos(z) + GiNaC::tan(x) + GiNaC::exp(y * z) + GiNaC::log(x * x + 1),
        GiNaC::asin(x / 2) + GiNaC::acos(y / 3) + GiNaC::atan(z) + GiNaC::sinh(x) + GiNaC::cosh(y) + GiNaC::tanh(z),
        GiNaC::abs(x - y) + GiNaC::sqrt(x * x + z * z),     // abs: GiNaC's diff; sqrt: a numeric power
        eomc::model::kepler_E(x * y, z / 4) * a,            // Kepler's E of both arguments
        a * a + 1,                                          // no variable: a zero row
    };
    check_against_derivative(rows, {x, y, z}, "hand-written");

    eomc::symbolic::Gradient gradient({z, x});
    const std::vector<ex> g = gradient(x * x * z);
    BOOST_TEST_REQUIRE(g.size() == 2u);
    BOOST_TEST((g[0] - x * x).expand().is_zero());  // ∂/∂z first, as asked
    BOOST_TEST((g[1] - 2 * x * z).expand().is_zero());
    const std::vector<ex> none = gradient(a + 1);
    BOOST_TEST((none[0].is_zero() && none[1].is_zero()));
}

// The row-major Jacobian helper lowers the explicit-solution kernels (n ≤ 2).
BOOST_AUTO_TEST_CASE(jacobian_helper_is_row_major) {
    const GiNaC::symbol x("x"), y("y");
    const std::vector<ex> J = eomc::symbolic::jacobian({x * y, x + GiNaC::sin(y)}, {x, y});
    BOOST_TEST_REQUIRE(J.size() == 4u);
    BOOST_TEST(J[0].is_equal(y));
    BOOST_TEST(J[1].is_equal(x));
    BOOST_TEST(J[2].is_equal(ex(1)));
    BOOST_TEST(J[3].is_equal(GiNaC::cos(y)));
}
