// DOP853's step-size controller, dop853.f's (safety 0.9, plain I controller) against eomc's
// default (Gustafsson's predictive controller added, safety 0.85), on eomc's kernel of the
// e = 0.6 Kepler orbit (generated/kepler_e06.hpp) over 10 periods, tolerances 1e-4 .. 1e-15 in
// quarter decades. Prints the rejection rate and, at a few error levels, the system calls each
// needs (work-precision front, log-log interpolation, as bench/compare_work_precision.py).
//
//   g++ -std=c++20 -O2 -ffp-contract=off -Iruntime/include -Igenerated -I/usr/include/eigen3
//       bench/dop853_controller.cpp -o build/dop853_controller && build/dop853_controller
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <eomc/runtime/stepper/dop853.hpp>
#include <eomc/runtime/integrate.hpp>

#include "kepler_e06.hpp"

namespace rt = eomc::runtime;
using K = eomc::models::KeplerE06;

namespace {

struct Sweep {
    std::vector<std::pair<double, double>> runs;  // (calls, error)
    std::size_t accepted = 0, rejected = 0;
};

Sweep sweep(const rt::Dop853<double>::Settings& settings) {
    const K::Parameters p{};
    auto sys = [&](double t, const rt::State<double>& x, rt::State<double>& d) { K::rhs(t, x.data(), d.data(), p); };
    Sweep s;
    for (int k = 16; k <= 60; ++k) {
        const double tol = std::pow(10.0, -k / 4.0);
        rt::State<double> x(K::initial_state.begin(), K::initial_state.end());
        rt::Dop853<double> stepper(settings, false);
        const rt::Stats st = rt::integrate_adaptive(stepper, sys, x, 0.0, 62.83185307179586, 0.0, rt::Tolerances{tol, tol},
                                                    [](double, const rt::State<double>&) {});
        double err = 0;  // after 10 periods the exact state is the initial one
        for (std::size_t i = 0; i < x.size(); ++i) err = std::max(err, std::abs(x[i] - K::initial_state[i]));
        s.runs.emplace_back(double(st.rhs_evals), err);
        s.accepted += st.accepted;
        s.rejected += st.rejected;
    }
    return s;
}

// Calls needed for `error` on the work-precision front (cheapest runs more accurate than all
// cheaper ones), interpolated in log-log; NaN outside.
double calls_at(std::vector<std::pair<double, double>> runs, double error) {
    std::sort(runs.begin(), runs.end());
    std::vector<std::pair<double, double>> front;
    for (const auto& r : runs)
        if (front.empty() || r.second < front.back().second) front.push_back(r);
    for (std::size_t i = 1; i < front.size(); ++i) {
        const auto [c0, e0] = front[i - 1];
        const auto [c1, e1] = front[i];
        if (e1 <= error && error <= e0) {
            const double f = std::log(error / e0) / std::log(e1 / e0);
            return std::exp(std::log(c0) + f * std::log(c1 / c0));
        }
    }
    return NAN;
}

}  // namespace

int main() {
    rt::Dop853<double>::Settings hairer = rt::Dop853<double>::default_settings();
    hairer.safety = 0.9;
    hairer.predictive = false;
    const Sweep a = sweep(hairer), b = sweep(rt::Dop853<double>::default_settings());
    std::printf("rejected attempts over the sweep: dop853.f controller %.1f%%, eomc default %.1f%%\n",
                100.0 * double(a.rejected) / double(a.accepted + a.rejected),
                100.0 * double(b.rejected) / double(b.accepted + b.rejected));
    std::printf("| error | dop853.f controller: calls | eomc default: calls | ratio |\n|---:|---:|---:|---:|\n");
    for (double e : {1e-4, 1e-6, 1e-8, 1e-9, 1e-10, 1e-11, 5e-12}) {
        const double ca = calls_at(a.runs, e), cb = calls_at(b.runs, e);
        std::printf("| %.0e | %.0f | %.0f | %.2f |\n", e, ca, cb, cb / ca);
    }
}
