// Embedding generated kernels: integrate two pendulums with eomc's runtime and check that
// each conserves its energy to the accuracy the tolerance promises. Exit status 0 = pass.
#include <cmath>
#include <cstdio>
#include <vector>

#include <eomc/runtime/runtime.hpp>

#include "double_pendulum.hpp"
#include "three_link_pendulum.hpp"

// Integrates Model from its scene's initial state to t_end; returns max |E(t) − E(0)|.
template <class Model>
double energy_drift(double t_end, double tol) {
    using State = eomc::runtime::State<double>;
    const typename Model::Parameters p;  // the scene's defaults
    State x(Model::initial_state.begin(), Model::initial_state.end());
    auto system = [&p](double t, const State& y, State& dydt) { Model::rhs(t, y.data(), dydt.data(), p); };

    const double e0 = Model::energy(0.0, x.data(), p);
    double drift = 0;
    eomc::runtime::Dopri5<double> stepper;
    const auto stats = eomc::runtime::integrate_adaptive(
        stepper, system, x, 0.0, t_end, 0.0, eomc::runtime::Tolerances{tol, tol},
        [&](double t, const State& y) { drift = std::fmax(drift, std::fabs(Model::energy(t, y.data(), p) - e0)); });
    std::printf("%-20s t = %5.1f  E0 = %+.12f  max|E - E0| = %.2e  (%zu steps, %zu rhs evaluations)\n",
                Model::scene_name, t_end, e0, drift, stats.accepted, stats.rhs_evals);
    return drift;
}

int main() {
    // DOPRI5's error per unit time is of the order of the tolerance, and these chaotic
    // pendulums have energies of order 10..60 J; 1e3·tol·|E0|·t_end/10 is a generous,
    // still meaningful bound (a wrong equation drifts by O(1)).
    const double tol = 1e-10, t_end = 10.0;
    bool ok = true;
    ok &= energy_drift<eomc::models::DoublePendulum>(t_end, tol) < 1e3 * tol * 60;
    ok &= energy_drift<eomc::models::ThreeLinkPendulum>(t_end, tol) < 1e3 * tol * 60;
    std::puts(ok ? "embed: energy conserved" : "embed: ENERGY DRIFT TOO LARGE");
    return ok ? 0 : 1;
}
