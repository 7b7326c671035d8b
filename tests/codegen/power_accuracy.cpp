// The checked-in kernels whose powers the printer writes as multiplications and sqrt (x^(5/2) =
// x*x*sqrt(x), x^4 = (x*x)*(x*x)) and whose half-integer powers share one sqrt and one division
// (codegen/cse.cpp, HalfPowers), against the derivation they came from: forcing, the explicit
// rates, the invariants and jacobian() (where generated: ∂/∂x of the explicit rates and of M⁻¹f,
// M inverted symbolically) in double at random states, against the same expressions of the
// first-order form evaluated by GiNaC in 40 digits, within a running rounding bound.
//
// The bound (first order in the unit round-off u = 2⁻⁵³; Higham, Accuracy and Stability, §3.1),
// formed node by node over the derived expression at the point, as an absolute error e(·):
//   an input            e = 0 (the state and the parameters are doubles)
//   a number c          e = 0 when an integer below 2⁵³, else u|c| (printed as S(a)/S(b) or rounded)
//   a sum of n terms    e = Σ e_i + (n−1) u Σ|v_i|            (any order of summation)
//   a product of n      e = Σ_i e_i Π_{j≠i}|v_j| + (n−1) u |v|
//   b^p, |p| ≤ 32       e = |v| (|p| e_b/|b| + (2P + 4) u)     the base's error scaled by |p| (the
//                        shared forms b^(−k/2) = d·b^((J−k)/2), d = 1/(b^((J−1)/2)·sqrt(b)), are
//                        the same power of the same computed b: the first-order propagation is p's),
//                        plus its own roundings: a sqrt, a division, the binary powerings to
//                        b^((J−1)/2) and b^((J−k)/2) and two products, at most 2P + 4 with P the
//                        largest |p| among the function's powers
//   f(a), libm          e = |f'(a)| e_a + 2u|f(a)|               (glibc: under 1 ulp)
// The canonical form the emitter prints factors sums (a·b + a·c = a·(b + c)), which only lowers
// this bound; the kernel must agree to twice it (the doubling covers the second-order terms).
#define BOOST_TEST_MODULE power_accuracy
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "foucault_pendulum.hpp"
#include "geo_equinoctial.hpp"
#include "kepler_e06.hpp"
#include "kovalevskaya_top.hpp"
#include "leo_drag.hpp"
#include "leo_j2.hpp"
#include "pleiades.hpp"
#include "relative_orbit.hpp"

#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"
#include "rounding_bound.hpp"
#include "scenes.hpp"

using GiNaC::ex;
using GiNaC::numeric;

namespace {

using test_support::Bounded;
using test_support::exact;
using test_support::RoundingBound;
using test_support::largest_power;

struct Stats {
    double worst = 0;  // the largest |kernel − reference| / bound seen
    int checked = 0;
};

// Kernel values `got` against the expressions at the inputs, each within twice its bound.
void compare(const std::string& what, const std::vector<ex>& expressions, const std::vector<double>& got,
             const GiNaC::exmap& inputs, Stats& stats) {
    RoundingBound bound(inputs, largest_power(expressions));
    for (std::size_t i = 0; i < expressions.size(); ++i) {
        const Bounded b = bound(expressions[i]);
        const double reference = b.value.to_double(), limit = 2 * b.error.to_double() + 1e-300;
        const double difference = std::abs(got[i] - reference);
        BOOST_TEST(difference <= limit, what << "[" << i << "]: kernel " << got[i] << ", derivation " << reference
                                              << ", |difference| " << difference << " > bound " << limit);
        stats.worst = std::max(stats.worst, difference / limit);
        ++stats.checked;
    }
}

// ∂ẋ/∂x as derived, row-major: the explicit rates and u̇ = M⁻¹f differentiated (M⁻¹ in closed form:
// small or diagonal M only).
std::vector<ex> derived_jacobian(const eomc::mechanics::FirstOrderForm& form) {
    const std::size_t n = form.state.size(), m = form.n_velocities();
    std::vector<ex> rates(n, ex(0));
    for (const auto& [index, rate] : form.explicit_rates) rates[index] = rate;
    if (m > 0) {
        const GiNaC::matrix inverse = GiNaC::ex_to<GiNaC::matrix>(form.mass_matrix).inverse();
        for (std::size_t k = 0; k < m; ++k) {
            ex u = 0;
            for (std::size_t l = 0; l < m; ++l) u += inverse(k, l) * form.forcing[l];
            rates[form.velocity_offset + k] = u;
        }
    }
    std::vector<ex> jacobian;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) jacobian.push_back(rates[i].diff(form.state[j].symbol));
    return jacobian;
}

template <class K>
void check_kernel(const std::string& scene) {
    GiNaC::Digits = 40;
    const auto model = test_support::bundled_model(scene);
    const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    BOOST_TEST_REQUIRE(form.state.size() == std::size_t(K::n_state));
    std::mt19937_64 random(20261128);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Stats stats;
    for (int point = 0; point < 8; ++point) {
        // Near the scene's initial state: 10 % relative, 0.01 absolute (entries that start at 0).
        double x[K::n_state];
        GiNaC::exmap inputs;
        const double t = 0.5 * (1 + unit(random));
        inputs[model.t] = exact(t);
        for (int i = 0; i < K::n_state; ++i) {
            x[i] = K::initial_state[i] * (1 + 0.1 * unit(random)) + 0.01 * unit(random);
            inputs[form.state[i].symbol] = exact(x[i]);
        }
        typename K::Parameters p;
        double values[K::n_parameters > 0 ? K::n_parameters : 1];
        std::memcpy(values, &p, sizeof p);
        for (int j = 0; j < K::n_parameters; ++j)
            for (const auto& parameter : model.parameters)
                if (parameter.name == K::parameter_names[j]) inputs[parameter.symbol] = exact(values[j]);

        std::vector<double> f(K::n_velocities), rates(K::n_state), invariants(K::n_invariants);
        K::forcing(t, x, f.data(), p);
        K::rhs(t, x, rates.data(), p);
        K::invariants(t, x, invariants.data(), p);
        compare(scene + " forcing", form.forcing, f, inputs, stats);
        std::vector<ex> explicit_rates;
        std::vector<double> explicit_got;
        for (const auto& [index, rate] : form.explicit_rates) {
            explicit_rates.push_back(rate);
            explicit_got.push_back(rates[index]);
        }
        compare(scene + " explicit rate", explicit_rates, explicit_got, inputs, stats);
        std::vector<ex> invariant_values;
        for (const auto& invariant : form.invariants) invariant_values.push_back(invariant.value);
        compare(scene + " invariant", invariant_values, invariants, inputs, stats);
        if constexpr (K::has_jacobian) {
            const std::vector<ex> expected = derived_jacobian(form);
            std::vector<double> J(std::size_t(K::n_state * K::n_state));
            K::jacobian(t, x, J.data(), p);
            compare(scene + " jacobian", expected, J, inputs, stats);
        }
    }
    BOOST_TEST_MESSAGE(scene << ": " << stats.checked << " values, largest |difference| / bound " << stats.worst);
}

}  // namespace

BOOST_AUTO_TEST_CASE(gravity_kernels_agree_with_their_derivation) {
    check_kernel<eomc::models::LeoJ2>("leo_j2");
    check_kernel<eomc::models::LeoDrag>("leo_drag");
    check_kernel<eomc::models::KeplerE06>("kepler_e06");
    check_kernel<eomc::models::RelativeOrbit>("relative_orbit");
    check_kernel<eomc::models::GeoEquinoctial>("geo_equinoctial");
}

BOOST_AUTO_TEST_CASE(many_body_and_rigid_kernels_agree_with_their_derivation) {
    check_kernel<eomc::models::Pleiades>("pleiades");
    check_kernel<eomc::models::FoucaultPendulum>("foucault_pendulum");
    check_kernel<eomc::models::KovalevskayaTop>("kovalevskaya_top");
}
