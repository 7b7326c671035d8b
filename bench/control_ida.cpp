// Program controls (issue 17, Mei ch. 3): eomc's controlled kernel against SUNDIALS IDA (Debian
// libsundials-dev 6.4) solving the same run as an index-1 DAE. The system is Meshchersky's problem
// (scenes/meshchersky_circle.toml): a particle m = 1 under gravity g = 9.81 kept on the circle
// ω = x² + y² − R² (R = 1; Erugin's law with α = 1, β = 2) at the speed φ = (ẋ² + ẏ² − v0²)/2
// (v0 = 3, κ = 3) by ideal controls, from (0, −1) with velocity (3, 0).
//
//   eomc  generated/meshchersky_circle.hpp's rhs (M u̇ = f + D λ, Ā u̇ = c solved at each call) with
//         the runtime's dopri5; λ read from the kernel's outputs at the output times.
//   IDA   unknowns (x, y, u, v, λ1, λ2), residuals
//           x' − u,  y' − v,  m u' − (2x λ1 + u λ2),  m v' − (−m g + 2y λ1 + v λ2),
//           ω̈ + 2α ω̇ + β² ω = 2(x u' + y v') + 2(u² + v²) + 2α (2xu + 2yv) + β² (x² + y² − R²),
//           φ̇ + κ φ = u u' + v v' + κ (u² + v² − v0²)/2,
//         the last two the programs' acceleration-level rows (algebraic: λ is their unknown, index 1
//         since Ā M⁻¹ D is regular off x v − y u = 0), initial λ by IDACalcIC.
//
// On the programmed motion (ω = φ = 0 at t = 0, so for all t) the particle runs round the circle at
// speed 3, x = sin 3t, y = −cos 3t, and by hand (radial and tangential balance, D = (∇ω, (u, v))):
//   λ1 = m (g y − v0²)/(2R²),   λ2 = m g v/v0²   (the tangential control cancels gravity's pull).
// Reported per tolerance: the largest |ω|, |φ| at the output times, the largest |λ − λ_exact|, the
// largest |λ_eomc − λ_IDA|, steps and wall time (median of 5).
//
//   cmake --build build --target bench_control_ida && build/bench/bench_control_ida
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <eomc/runtime/integrate.hpp>
#include <eomc/runtime/stepper/dopri5.hpp>

#include "meshchersky_circle.hpp"

namespace rt = eomc::runtime;
using Kernel = eomc::models::MeshcherskyCircle;

namespace {

constexpr double m = 1.0, g = 9.81, R = 1.0, v0 = 3.0, alpha = 1.0, beta = 2.0, kappa = 3.0, t_end = 5.0;
constexpr int n_out = 51;  // every 0.1

struct Run {
    std::vector<std::array<double, 6>> at;  // x, y, u, v, λ1, λ2 at the output times
    long steps = 0;
    long error_fails = 0, newton_fails = 0;  // IDA's error test and Newton failures
    double wall = 0;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::vector<double> output_times() {
    std::vector<double> t;
    for (int i = 0; i < n_out; ++i) t.push_back(t_end * i / (n_out - 1));
    return t;
}

Run eomc_run(double rtol) {
    Run out;
    std::vector<double> walls;
    for (int repeat = 0; repeat < 5; ++repeat) {
        out.at.clear();
        const Kernel::Parameters p{};
        auto sys = [&](double t, const rt::State<double>& x, rt::State<double>& dxdt) {
            Kernel::rhs(t, x.data(), dxdt.data(), p);
        };
        rt::State<double> x(Kernel::initial_state.begin(), Kernel::initial_state.end());
        rt::Dopri5<double> stepper;
        const auto start = std::chrono::steady_clock::now();
        const auto stats = rt::integrate_times(stepper, sys, x, output_times(), 0.0, rt::Tolerances{rtol, rtol * 1e-2},
                                               [&](double t, const rt::State<double>& xs) {
                                                   std::array<double, Kernel::n_outputs> o{};
                                                   Kernel::outputs(t, xs.data(), o.data(), p);
                                                   out.at.push_back({xs[0], xs[1], xs[2], xs[3], o[2], o[3]});
                                               });
        walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        out.steps = long(stats.accepted);
    }
    out.wall = median(walls);
    return out;
}

int residual(sunrealtype, N_Vector yy, N_Vector yp, N_Vector rr, void*) {
    const sunrealtype* y = N_VGetArrayPointer(yy);
    const sunrealtype* d = N_VGetArrayPointer(yp);
    sunrealtype* r = N_VGetArrayPointer(rr);
    const double x = y[0], z = y[1], u = y[2], v = y[3], l1 = y[4], l2 = y[5];
    r[0] = d[0] - u;
    r[1] = d[1] - v;
    r[2] = m * d[2] - (2 * x * l1 + u * l2);
    r[3] = m * d[3] - (-m * g + 2 * z * l1 + v * l2);
    r[4] = 2 * (x * d[2] + z * d[3]) + 2 * (u * u + v * v) + 2 * alpha * (2 * x * u + 2 * z * v) +
           beta * beta * (x * x + z * z - R * R);
    r[5] = u * d[2] + v * d[3] + kappa * (u * u + v * v - v0 * v0) / 2;
    return 0;
}

void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string("IDA: ") + what + " failed with flag " + std::to_string(flag));
}

Run ida_run(double rtol, bool suppress_algebraic) {
    Run out;
    std::vector<double> walls;
    for (int repeat = 0; repeat < 5; ++repeat) {
        out.at.clear();
        SUNContext ctx = nullptr;
        check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
        N_Vector yy = N_VNew_Serial(6, ctx), yp = N_VNew_Serial(6, ctx), id = N_VNew_Serial(6, ctx);
        sunrealtype* y = N_VGetArrayPointer(yy);
        const std::array<double, 6> y0{0, -1, 3, 0, 0, 0};
        for (int i = 0; i < 6; ++i) {
            y[i] = y0[std::size_t(i)];
            N_VGetArrayPointer(yp)[i] = 0;
            N_VGetArrayPointer(id)[i] = i < 4 ? 1.0 : 0.0;  // λ algebraic
        }
        N_VGetArrayPointer(yp)[0] = 3;  // x' = u
        const auto start = std::chrono::steady_clock::now();
        void* mem = IDACreate(ctx);
        check(IDAInit(mem, residual, 0.0, yy, yp), "IDAInit");
        check(IDASStolerances(mem, rtol, rtol * 1e-2), "IDASStolerances");
        SUNMatrix A = SUNDenseMatrix(6, 6, ctx);
        SUNLinearSolver LS = SUNLinSol_Dense(yy, A, ctx);
        check(IDASetLinearSolver(mem, LS, A), "IDASetLinearSolver");
        check(IDASetId(mem, id), "IDASetId");
        check(IDASetMaxNumSteps(mem, 1000000), "IDASetMaxNumSteps");
        check(IDASetSuppressAlg(mem, suppress_algebraic ? SUNTRUE : SUNFALSE), "IDASetSuppressAlg");
        check(IDACalcIC(mem, IDA_YA_YDP_INIT, 0.1), "IDACalcIC");
        check(IDAGetConsistentIC(mem, yy, yp), "IDAGetConsistentIC");
        out.at.push_back({y[0], y[1], y[2], y[3], y[4], y[5]});
        const auto times = output_times();
        for (std::size_t i = 1; i < times.size(); ++i) {
            sunrealtype reached = 0;
            // Each output time a step's end, not interpolated: λ is then the corrector's value.
            check(IDASetStopTime(mem, times[i]), "IDASetStopTime");
            check(IDASolve(mem, times[i], &reached, yy, yp, IDA_NORMAL), "IDASolve");
            out.at.push_back({y[0], y[1], y[2], y[3], y[4], y[5]});
        }
        walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        long steps = 0, error_fails = 0, newton_fails = 0;
        IDAGetNumSteps(mem, &steps);
        IDAGetNumErrTestFails(mem, &error_fails);
        IDAGetNumNonlinSolvConvFails(mem, &newton_fails);
        out.steps = steps;
        out.error_fails = error_fails;
        out.newton_fails = newton_fails;
        IDAFree(&mem);
        SUNLinSolFree(LS);
        SUNMatDestroy(A);
        N_VDestroy(yy);
        N_VDestroy(yp);
        N_VDestroy(id);
        SUNContext_Free(&ctx);
    }
    out.wall = median(walls);
    return out;
}

struct Errors {
    double omega = 0, phi = 0, lambda = 0;
};

Errors errors(const Run& r) {
    Errors e;
    const auto times = output_times();
    for (std::size_t i = 0; i < r.at.size(); ++i) {
        const auto& s = r.at[i];
        e.omega = std::max(e.omega, std::abs(s[0] * s[0] + s[1] * s[1] - R * R));
        e.phi = std::max(e.phi, std::abs((s[2] * s[2] + s[3] * s[3] - v0 * v0) / 2));
        const double t = times[i], y = -std::cos(3 * t), v = 3 * std::sin(3 * t);
        e.lambda = std::max({e.lambda, std::abs(s[4] - m * (g * y - v0 * v0) / (2 * R * R)),
                             std::abs(s[5] - m * g * v / (v0 * v0))});
    }
    return e;
}

}  // namespace

std::string number(double x) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2e", x);
    return buffer;
}

int main() {
    std::printf("| rtol | tool | max abs omega | max abs phi | max abs(lambda - exact) | max abs(lambda - lambda_eomc) "
                "| steps | error test, Newton failures | wall (median of 5) |\n|---|---|---|---|---|---|---|---|---|\n");
    for (double rtol : {1e-6, 1e-8, 1e-10}) {
        const Run a = eomc_run(rtol), b = ida_run(rtol, false), c = ida_run(rtol, true);
        for (const auto& [name, r] : {std::pair{"eomc dopri5", &a}, std::pair{"IDA, lambda in the error test", &b},
                                      std::pair{"IDA, lambda out of it (IDASetSuppressAlg)", &c}}) {
            double between = 0;
            for (std::size_t i = 0; i < a.at.size(); ++i)
                between = std::max({between, std::abs(a.at[i][4] - r->at[i][4]), std::abs(a.at[i][5] - r->at[i][5])});
            const Errors e = errors(*r);
            const std::string failures = r == &a ? "-" : std::to_string(r->error_fails) + ", " + std::to_string(r->newton_fails);
            std::printf("| %.0e | %s | %.2e | %.2e | %.2e | %s | %ld | %s | %.3g ms |\n", rtol, name, e.omega, e.phi,
                        e.lambda, r == &a ? "-" : number(between).c_str(), r->steps, failures.c_str(), 1e3 * r->wall);
        }
    }
    return 0;
}
