// Long runs of the symplectic integrators on the Kepler problem: does the energy error grow like
// sqrt(t) (Brouwer's law: round-off as a random walk, no secular drift) or faster?
//
// The kernel is eomc's own, generated/kepler_e06.hpp (Cartesian Kepler, mu = 1, a = 1). The
// orbit starts at pericentre with eccentricity e (default 0.6, the scene's), period 2 pi, and is
// integrated with a fixed step of 2 pi / N for the given number of orbits, with Gauss-Legendre 6
// or 8 (fixed-point stage iteration) or Kahan-Li 8 (the splitting stepper, fed the kernel's q''
// evaluated at zero velocity: for this Lagrangian q'' depends on q alone), with compensated
// summation on or off. The energy is evaluated in long double at the end of every orbit (same
// phase, so the bounded periodic part of a symplectic method's energy error does not enter) and
// its error |E - E0| (RMS over realizations, see --realizations) is binned in time, four bins per decade; the slope of log RMS(error) against
// log t over bins from 10 orbits on is the growth exponent (0.5: random walk, 1: linear drift).
//
// Build and run (from the repository root):
//   g++ -std=c++20 -O2 -ffp-contract=off -Iruntime/include -Igenerated -I/usr/include/eigen3
//       bench/brouwer.cpp -o build/brouwer
//   build/brouwer --method gl8 --orbits 100000 --steps-per-orbit 400 [--uncompensated] [--e 0.6]
//                 [--realizations R] [--csv FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <eomc/runtime/stepper/gauss_legendre.hpp>
#include <eomc/runtime/stepper/splitting.hpp>

#include "kepler_e06.hpp"

namespace rt = eomc::runtime;
using K = eomc::models::KeplerE06;

namespace {

const K::Parameters parameters{};

long double energy(const rt::State<double>& x) {
    const long double xl[4] = {x[0], x[1], x[2], x[3]};
    long double e = 0;
    K::invariants<long double>(0.0L, xl, &e, parameters);
    return e;
}

struct Series {
    std::vector<double> t, error;
    long double e0 = 0;
    double max_error = 0;
};

template <class Stepper, class Sys>
Series run(Stepper stepper, Sys& sys, rt::State<double> x, long orbits, double per_orbit) {
    Series s;
    s.e0 = energy(x);
    const double period = 2 * M_PI, h = period / per_orbit;
    const auto total = static_cast<long>(std::ceil(double(orbits) * per_orbit));
    for (long k = 0; k < total; ++k) {
        // Step k runs from k h to (k + 1) h, both computed afresh (no accumulated time). The
        // energy is sampled after the last step of every orbit.
        stepper.do_step(sys, x, double(k) * h, double(k + 1) * h - double(k) * h);
        if (std::floor(double(k + 1) / per_orbit) > std::floor(double(k) / per_orbit)) {
            const double err = double(std::fabs(energy(x) - s.e0));
            s.t.push_back(double(k + 1) * h);
            s.error.push_back(err);
            s.max_error = std::max(s.max_error, err);
            if (!std::isfinite(err)) break;
        }
    }
    return s;
}

// Least-squares slope of log10 RMS(error) over time bins (4 per decade) from t_min on.
double growth_exponent(const Series& s, double t_min, std::vector<std::pair<double, double>>& bins) {
    std::vector<double> sum, count, tsum;
    for (std::size_t i = 0; i < s.t.size(); ++i) {
        if (s.t[i] < t_min) continue;
        const auto b = static_cast<std::size_t>(std::floor(4 * std::log10(s.t[i] / t_min)));
        if (sum.size() <= b) sum.resize(b + 1), count.resize(b + 1), tsum.resize(b + 1);
        sum[b] += s.error[i] * s.error[i];
        tsum[b] += std::log10(s.t[i]);
        count[b] += 1;
    }
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (std::size_t b = 0; b < sum.size(); ++b) {
        if (count[b] == 0 || sum[b] <= 0) continue;
        const double lx = tsum[b] / count[b], ly = 0.5 * std::log10(sum[b] / count[b]);
        bins.emplace_back(std::pow(10.0, lx), std::pow(10.0, ly));
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, n += 1;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

[[noreturn]] void usage() {
    std::fprintf(stderr, "usage: brouwer --method gl6|gl8|kahanli8 [--orbits N] [--steps-per-orbit N] "
                         "[--uncompensated] [--e E] [--realizations R] [--csv FILE]\n");
    std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
    std::string method, csv;
    long orbits = 1000;
    double per_orbit = 400;
    int realizations = 1;
    bool compensated = true;
    double e = 0.6;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string { if (i + 1 >= argc) usage(); return argv[++i]; };
        if (a == "--method") method = value();
        else if (a == "--orbits") orbits = std::atol(value().c_str());
        else if (a == "--steps-per-orbit") per_orbit = std::atof(value().c_str());
        else if (a == "--uncompensated") compensated = false;
        else if (a == "--e") e = std::atof(value().c_str());
        else if (a == "--csv") csv = value();
        else if (a == "--realizations") realizations = std::atoi(value().c_str());
        else usage();
    }
    if (orbits < 1 || !(per_orbit >= 1) || realizations < 1 || !(e >= 0 && e < 1)) usage();
    // Pericentre of the orbit with a = 1: (1 - e, 0), speed sqrt((1 + e) / (1 - e)).
    const rt::State<double> x0{1 - e, 0, 0, std::sqrt((1 + e) / (1 - e))};

    auto rhs = [](double t, const rt::State<double>& x, rt::State<double>& dxdt) { K::rhs(t, x.data(), dxdt.data(), parameters); };
    auto acceleration = [](double t, const rt::State<double>& q, rt::State<double>& a) {
        const double x[4] = {q[0], q[1], 0, 0};
        double d[4];
        K::rhs(t, x, d, parameters);
        a[0] = d[2];
        a[1] = d[3];
    };
    rt::GaussLegendreOptions gl;
    gl.compensated = compensated;
    rt::SplittingOptions sp;
    sp.compensated = compensated;

    const auto start = std::chrono::steady_clock::now();
    // Realization k starts on the same orbit turned by k * 0.1 rad: the same dynamics, other
    // round-off. Their squared errors are averaged orbit by orbit (an ensemble RMS, which a
    // random walk makes grow like sqrt(t) far more cleanly than one path does).
    Series s;
    for (int k = 0; k < realizations; ++k) {
        const double c = std::cos(0.1 * k), sn = std::sin(0.1 * k);
        const rt::State<double> xk{x0[0] * c, x0[0] * sn, -x0[3] * sn, x0[3] * c};
        Series one;
        if (method == "gl6") one = run(rt::Gl6<double>(gl), rhs, xk, orbits, per_orbit);
        else if (method == "gl8") one = run(rt::Gl8<double>(gl), rhs, xk, orbits, per_orbit);
        else if (method == "kahanli8") one = run(rt::KahanLi8<double>(sp), acceleration, xk, orbits, per_orbit);
        else usage();
        if (k == 0) {
            s = one;
            for (double& e2 : s.error) e2 *= e2;
        } else {
            for (std::size_t i = 0; i < std::min(s.error.size(), one.error.size()); ++i) s.error[i] += one.error[i] * one.error[i];
            s.max_error = std::max(s.max_error, one.max_error);
        }
    }
    for (double& e2 : s.error) e2 = std::sqrt(e2 / realizations);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::vector<std::pair<double, double>> bins;
    const double slope = growth_exponent(s, 10 * 2 * M_PI, bins);
    std::printf("%s e=%g %ld orbits x %g steps, %d realization%s, compensated %s: RMS |E - E0| at end %.3g, max %.3g "
                "(|E0| = %.3g), growth exponent %.3f, %.1f s\n",
                method.c_str(), e, orbits, per_orbit, realizations, realizations == 1 ? "" : "s",
                compensated ? "on" : "off", s.error.empty() ? NAN : s.error.back(), s.max_error,
                double(std::fabs(s.e0)), slope, seconds);
    std::printf("  RMS |E - E0| by time bin (orbits: error):");
    for (const auto& [t, err] : bins) std::printf(" %.3g: %.2g", t / (2 * M_PI), err);
    std::printf("\n");
    if (!csv.empty()) {
        std::FILE* f = std::fopen(csv.c_str(), "w");
        if (!f) {
            std::perror(csv.c_str());
            return 1;
        }
        std::fprintf(f, "orbit,energy_error\n");
        for (std::size_t i = 0; i < s.t.size(); ++i) std::fprintf(f, "%ld,%.6g\n", long(i + 1), s.error[i]);
        std::fclose(f);
    }
    return 0;
}
