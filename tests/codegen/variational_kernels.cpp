// Variational equations (Hairer, Nørsett & Wanner, Solving ODEs I, §I.14) of kernels generated
// with --variational, against Poincaré's theorem: if I(x) is a first integral, then along a
// solution x(t) with its variations δx(t) = Φ(t) δx(0), the linear form ∇I(x(t)) · δx(t) is
// constant, i.e. the row w(t) = ∇I(x(t))ᵀ Φ(t) equals ∇I(x(0))ᵀ for all t. Each w_j is a function
// of the extended state y = (x, Φ), conserved by the extended equations, so the drift of a
// numerical solution is held to the bound physics_support.hpp derives from the accepted steps'
// tolerances. ∇I comes from the complex step, Im I(x + i h e_k)/h, exact to round-off (no
// subtraction).
#define BOOST_TEST_MODULE variational
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <complex>
#include <functional>
#include <vector>

#include "bead_on_hoop.hpp"
#include "kepler_cartesian.hpp"
#include "physics_support.hpp"

namespace rt = eomc::runtime;
using C = std::complex<double>;

namespace {

// The extended system y = (x, Φ) of a kernel, through its variational_rhs.
template <class Model>
struct VariationalSystem {
    typename Model::Parameters p{};
    void operator()(double t, const rt::State<double>& y, rt::State<double>& dydt) const {
        Model::variational_rhs(t, y.data(), dydt.data(), p);
    }
};

template <class Model>
std::vector<double> with_identity(const std::array<double, Model::n_state>& x0) {
    constexpr int n = Model::n_state;
    std::vector<double> y(Model::n_variational, 0.0);
    for (int i = 0; i < n; ++i) y[std::size_t(i)] = x0[std::size_t(i)], y[std::size_t(n + i * n + i)] = 1;
    return y;
}

// ∇I at x by the complex step; I is called on complex states.
template <int n>
std::array<double, n> gradient(const std::function<C(const C*)>& I, const double* x) {
    constexpr double h = 1e-30;
    std::array<double, n> g{};
    for (int k = 0; k < n; ++k) {
        std::array<C, n> xc;
        for (int i = 0; i < n; ++i) xc[std::size_t(i)] = x[i];
        xc[std::size_t(k)] += C(0, h);
        g[std::size_t(k)] = I(xc.data()).imag() / h;
    }
    return g;
}

// w_j(y) = Σ_i ∂I/∂x_i(x) Φ_ij.
template <int n>
double poincare_form(const std::function<C(const C*)>& I, const std::vector<double>& y, int j) {
    const auto g = gradient<n>(I, y.data());
    double w = 0;
    for (int i = 0; i < n; ++i) w += g[std::size_t(i)] * y[std::size_t(n + i * n + j)];
    return w;
}

struct Integral {
    const char* name;
    std::function<C(const C*)> value;
};

// Integrates the extended system and checks every w_j of every integral against its bound;
// returns the largest drift relative to its bound (for the negative control).
template <class Model>
double check_poincare(const std::vector<Integral>& integrals, double t1, const rt::Tolerances& tol, double terms) {
    constexpr int n = Model::n_state;
    VariationalSystem<Model> sys;
    const std::vector<double> y0 = with_identity<Model>(Model::initial_state);
    std::vector<double> y = y0;
    rt::Dopri5<double> stepper;
    const auto steps = phys::run(stepper, sys, y, 0.0, t1, tol);
    double worst = 0;
    for (const auto& integral : integrals)
        for (int j = 0; j < n; ++j) {
            auto w = [&](const std::vector<double>& state) { return poincare_form<n>(integral.value, state, j); };
            const double drift = std::abs(w(y) - w(y0));
            const double bound = phys::invariant_drift_bound<double>(steps, w, terms);
            BOOST_TEST_INFO(integral.name << ", column " << j << ": drift " << drift << ", bound " << bound);
            BOOST_TEST(drift <= bound);
            worst = std::max(worst, drift / bound);
        }
    return worst;
}

}  // namespace

// The Kepler problem: energy (the kernel's own invariant), angular momentum and both components
// of the Runge–Lenz vector, over three orbits of e = 0.5 (Φ grows linearly through the shear
// of the period with energy, so its entries reach ~30 and w is a sum of large terms).
BOOST_AUTO_TEST_CASE(kepler_integrals_give_constant_linear_forms) {
    using Model = eomc::models::KeplerCartesian;
    const Model::Parameters P{};
    const double mu = P.mu;
    const std::vector<Integral> integrals{
        {"energy", [](const C* x) { C e[Model::n_invariants]; Model::invariants<C>(C(0), x, e, Model::Parameters{}); return e[0]; }},
        {"angular momentum", [](const C* x) { return x[0] * x[3] - x[1] * x[2]; }},
        {"Runge-Lenz x", [mu](const C* x) {
             const C L = x[0] * x[3] - x[1] * x[2];
             return x[3] * L - mu * x[0] / std::sqrt(x[0] * x[0] + x[1] * x[1]);
         }},
        {"Runge-Lenz y", [mu](const C* x) {
             const C L = x[0] * x[3] - x[1] * x[2];
             return -x[2] * L - mu * x[1] / std::sqrt(x[0] * x[0] + x[1] * x[1]);
         }},
    };
    check_poincare<Model>(integrals, 3 * 2 * M_PI, rt::Tolerances{1e-11, 1e-11}, 100.0);
}

// The bead on the spinning hoop: the Jacobi integral of the kept equations.
BOOST_AUTO_TEST_CASE(hoop_jacobi_integral_gives_a_constant_linear_form) {
    using Model = eomc::models::BeadOnHoop;
    const std::vector<Integral> integrals{
        {"Jacobi", [](const C* x) { C e[Model::n_invariants]; Model::invariants<C>(C(0), x, e, Model::Parameters{}); return e[0]; }},
    };
    check_poincare<Model>(integrals, 5.0, rt::Tolerances{1e-11, 1e-11}, 10.0);
}

// The test can fail: a quantity that is not an integral (the Kepler radius) gives a form that
// moves by orders of magnitude more than the bound.
BOOST_AUTO_TEST_CASE(a_non_integral_breaks_the_bound) {
    using Model = eomc::models::KeplerCartesian;
    constexpr int n = Model::n_state;
    VariationalSystem<Model> sys;
    const std::vector<double> y0 = with_identity<Model>(Model::initial_state);
    std::vector<double> y = y0;
    rt::Dopri5<double> stepper;
    const rt::Tolerances tol{1e-11, 1e-11};
    const auto steps = phys::run(stepper, sys, y, 0.0, 1.0, tol);
    const std::function<C(const C*)> radius = [](const C* x) { return std::sqrt(x[0] * x[0] + x[1] * x[1]); };
    auto w = [&](const std::vector<double>& state) { return poincare_form<n>(radius, state, 0); };
    BOOST_TEST(std::abs(w(y) - w(y0)) > 1e3 * phys::invariant_drift_bound<double>(steps, w, 100.0));
}
