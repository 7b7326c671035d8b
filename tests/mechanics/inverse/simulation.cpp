// Simulations of Newtonian scenes against the Lagrangian scenes `eomc inverse --emit-scene`
// constructs from them (damped oscillator with the Caldirola–Kanai L, central force with the
// metric multiplier, pendulum as given). Both kernels are integrated with Dopri5 at the same
// tolerances; the final states must agree to within the sum of the two runs' global error
// bounds, each propagated from every accepted step's tolerance through the variational
// equation (tests/physics/physics_support.hpp). The bound is shown to be discriminating: the
// same comparison with a parameter of the Lagrangian scene changed by 0.1% fails it by orders
// of magnitude. Also the Santilli residual functions of the Newtonian kernels along the runs.
#define BOOST_TEST_MODULE inverse_simulation
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "central_force_polar.hpp"
#include "central_force_polar_lagrangian.hpp"
#include "damped_oscillator.hpp"
#include "damped_oscillator_lagrangian.hpp"
#include "pendulum_fundamental.hpp"
#include "pendulum_fundamental_lagrangian.hpp"
#include "physics_support.hpp"

namespace rt = eomc::runtime;
using namespace eomc::models;

namespace {

const rt::Tolerances tolerances{1e-10, 1e-12};

struct Run {
    std::vector<double> x;      // final state
    std::vector<double> bound;  // bound on its global error, per component
};

template <class Model>
Run run(const typename Model::Parameters& p, double t1) {
    phys::KernelSystem<Model, double> sys;
    sys.p = p;
    const std::vector<double> x0(Model::initial_state.begin(), Model::initial_state.end());
    std::vector<double> x = x0;
    rt::Dopri5<double> stepper;
    const auto steps = phys::run(stepper, sys, x, 0.0, t1, tolerances);
    return {x, phys::propagated_error_bound<Model, double>(steps, x0, 0.0, p, tolerances)};
}

// max_i |x_N,i − x_L,i| / (b_N,i + b_L,i): ≤ 1 when the runs agree within their error bounds.
template <class N, class L>
double mismatch(const typename L::Parameters& lagrangian_parameters, double t1) {
    static_assert(N::n_state == L::n_state);
    for (int i = 0; i < N::n_state; ++i) {
        BOOST_TEST(std::string(N::state_names[std::size_t(i)]) == L::state_names[std::size_t(i)]);
        BOOST_TEST(N::initial_state[std::size_t(i)] == L::initial_state[std::size_t(i)]);
    }
    const Run n = run<N>(typename N::Parameters{}, t1);
    const Run l = run<L>(lagrangian_parameters, t1);
    double worst = 0;
    for (int i = 0; i < N::n_state; ++i) {
        const double bound = n.bound[std::size_t(i)] + l.bound[std::size_t(i)];
        BOOST_TEST_MESSAGE(N::state_names[std::size_t(i)] << ": |x_N − x_L| = " << std::abs(n.x[std::size_t(i)] - l.x[std::size_t(i)])
                                                          << ", bound " << bound);
        // A bound that could never fail is a defect: it must be far below the state's size.
        BOOST_TEST(bound < 1e-5 * (1 + std::abs(n.x[std::size_t(i)])));
        worst = std::max(worst, std::abs(n.x[std::size_t(i)] - l.x[std::size_t(i)]) / bound);
    }
    return worst;
}

}  // namespace

BOOST_AUTO_TEST_CASE(damped_oscillator_and_its_caldirola_kanai_lagrangian_agree) {
    {
        const double ratio = mismatch<DampedOscillator, DampedOscillatorLagrangian>({}, 20.0);
        BOOST_TEST(ratio <= 1.0);
    }
    DampedOscillatorLagrangian::Parameters wrong;
    wrong.gamma *= 1.001;
    {
        const double ratio = mismatch<DampedOscillator, DampedOscillatorLagrangian>(wrong, 20.0);
        BOOST_TEST(ratio > 100.0);
    }
}

BOOST_AUTO_TEST_CASE(damped_oscillator_follows_the_closed_form) {
    // x = e^{−γt/2} (x0 cos ωt + (v0 + γx0/2)/ω sin ωt), ω² = w² − γ²/4.
    const DampedOscillator::Parameters p;
    const double t1 = 20.0, x0 = DampedOscillator::initial_state[0], v0 = DampedOscillator::initial_state[1];
    const double omega = std::sqrt(p.w * p.w - p.gamma * p.gamma / 4);
    const double c = std::cos(omega * t1), s = std::sin(omega * t1), e = std::exp(-p.gamma * t1 / 2);
    const double a = x0, b = (v0 + p.gamma * x0 / 2) / omega;
    const double x = e * (a * c + b * s);
    const double v = -p.gamma / 2 * x + e * omega * (b * c - a * s);
    const Run r = run<DampedOscillator>(p, t1);
    BOOST_TEST(std::abs(r.x[0] - x) <= r.bound[0]);
    BOOST_TEST(std::abs(r.x[1] - v) <= r.bound[1]);
}

BOOST_AUTO_TEST_CASE(central_force_and_its_metric_lagrangian_agree) {
    {
        const double ratio = mismatch<CentralForcePolar, CentralForcePolarLagrangian>({}, 10.0);
        BOOST_TEST(ratio <= 1.0);
    }
    CentralForcePolarLagrangian::Parameters wrong;
    wrong.k *= 1.001;
    {
        const double ratio = mismatch<CentralForcePolar, CentralForcePolarLagrangian>(wrong, 10.0);
        BOOST_TEST(ratio > 100.0);
    }
}

BOOST_AUTO_TEST_CASE(pendulum_and_its_lagrangian_agree) {
    {
        const double ratio = mismatch<PendulumFundamental, PendulumFundamentalLagrangian>({}, 5.0);
        BOOST_TEST(ratio <= 1.0);
    }
    PendulumFundamentalLagrangian::Parameters wrong;
    wrong.g *= 1.001;
    {
        const double ratio = mismatch<PendulumFundamental, PendulumFundamentalLagrangian>(wrong, 5.0);
        BOOST_TEST(ratio > 100.0);
    }
}

// The residual functions along a trajectory: zero for the self-adjoint pendulum; for the
// central force, the non-zero ones equal their closed forms (S3(r,θ) = 2θ̇/r − 2rθ̇,
// S3(θ,θ) = 4ṙ/r, S4(r,θ;θ) = r + 1/r, S5(r,θ) = ṙθ̇ (1 + 1/r²)) and the others vanish.
template <class Model, class Check>
void along_trajectory(double t1, Check&& check) {
    phys::KernelSystem<Model, double> sys;
    std::vector<double> x(Model::initial_state.begin(), Model::initial_state.end());
    rt::Dopri5<double> stepper;
    int evaluated = 0;
    phys::run(stepper, sys, x, 0.0, t1, tolerances, [&](const phys::Step<double>& st, const rt::Dopri5<double>&) {
        std::array<double, Model::n_santilli_residuals> out;
        Model::santilli_residuals(st.t_new, st.x_new.data(), out.data(), sys.p);
        check(st.x_new, out);
        ++evaluated;
    });
    BOOST_TEST(evaluated > 10);
}

BOOST_AUTO_TEST_CASE(santilli_residuals_along_the_runs) {
    along_trajectory<PendulumFundamental>(5.0, [](const std::vector<double>&, const auto& out) {
        for (double r : out) BOOST_TEST(r == 0.0);
    });
    BOOST_TEST(std::string(CentralForcePolar::santilli_residual_names[4]) == "S3(r,theta)");
    along_trajectory<CentralForcePolar>(10.0, [](const std::vector<double>& x, const auto& out) {
        const double r = x[0], rd = x[2], thd = x[3];
        const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-14 * (1 + std::abs(b)); };
        for (std::size_t k = 0; k < out.size(); ++k) {
            const std::string name = CentralForcePolar::santilli_residual_names[k];
            const double expected = name == "S3(r,theta)"       ? 2 * thd / r - 2 * r * thd
                                    : name == "S3(theta,theta)" ? 4 * rd / r
                                    : name == "S4(r,theta;theta)" ? r + 1 / r
                                    : name == "S5(r,theta)"     ? rd * thd * (1 + 1 / (r * r))
                                                                : 0.0;
            BOOST_TEST(near(out[k], expected), name << " = " << out[k] << ", expected " << expected);
        }
    });
    along_trajectory<DampedOscillator>(20.0, [](const std::vector<double>&, const auto& out) {
        BOOST_TEST(out[0] == 2 * DampedOscillator::Parameters{}.gamma);
    });
}
