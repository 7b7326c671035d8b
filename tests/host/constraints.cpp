// Constraint rows end to end (issue 14, the kernel side): a Cartesian pendulum (x, y) with the
// rod x² + y² = l² appended by hand as a ConstraintRow, lowered, emitted, compiled and run through
// eomc simulate, against the polar pendulum θ; the multiplier against the rod's tension; and the
// drift of the rod's residual under projection (Hairer, Lubich, Wanner, Geometric Numerical
// Integration, 2nd ed., IV.4), Baumgarte's stabilisation (Comput. Methods Appl. Mech. Eng. 1
// (1972) 1) and none.
#define BOOST_TEST_MODULE simulate_constraints
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "host/toolchain.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"

#include "csv.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;
using eomc::mechanics::Stabilization;

namespace {

constexpr double m = 1.5, g = 9.81, l = 1.2, theta0 = 0.5;

const char* const cartesian = R"toml([scene]
name = "pendulum_cartesian"
[parameters]
m = 1.5
g = 9.81
l = 1.2
[coordinates]
x = { initial = 0.5, rate = 0.0 }
y = { initial = -1.0, rate = 0.0 }
[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"
)toml";

const char* const polar = R"toml([scene]
name = "pendulum_polar"
[parameters]
m = 1.5
g = 9.81
l = 1.2
[coordinates]
theta = { initial = 0.5, rate = 0.0 }
[lagrangian]
T = "m*l^2*theta_dot^2/2"
V = "-m*g*l*cos(theta)"
)toml";

const GiNaC::symbol& parameter(const eomc::model::Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    throw std::runtime_error("no parameter " + name);
}

// The Cartesian pendulum's kernel with the rod as a row stabilised as asked.
test_support::Kernel rod_kernel(Stabilization stabilization, double alpha = 0.0, double beta = 0.0) {
    const auto model = test_support::model_of(cartesian);
    auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    BOOST_REQUIRE(form.state.size() == 4u);
    const GiNaC::ex x = form.state[0].symbol, y = form.state[1].symbol, xd = form.state[2].symbol,
                    yd = form.state[3].symbol, L = parameter(model, "l");
    eomc::mechanics::ConstraintRow row;
    row.name = "rod";
    row.holonomic = true;
    row.position = x * x + y * y - L * L;
    row.velocity = 2 * x * xd + 2 * y * yd;
    row.W = {2 * x, 2 * y};
    row.bias = 2 * xd * xd + 2 * yd * yd;
    row.lambda = GiNaC::symbol("lambda_rod");
    row.stabilization = stabilization;
    row.alpha = alpha;
    row.beta = beta;
    form.constraints.push_back(row);
    const auto ir = eomc::codegen::lower(model, form, nullptr, {.jacobian = true});  // compiled and called below
    return {eomc::codegen::emit_header(ir, {EOMC_VERSION, false}), model.struct_name};
}

eomc::host::SimulationRequest request(const test_support::Kernel& k, double t_end, double rtol) {
    auto r = test_support::simulation_request(k, t_end);
    r.rtol = rtol;
    r.atol = rtol * 1e-2;
    if (k.struct_name != "PendulumPolar") {
        r.overrides = {{"x", l * std::sin(theta0)}, {"y", -l * std::cos(theta0)}};
    }
    return r;
}

// The period of the pendulum from θ0: 4 K(sin(θ0/2)) √(l/g), K by the arithmetic-geometric mean.
double period() {
    double a = 1.0, b = std::cos(theta0 / 2);
    for (int i = 0; i < 30; ++i) {
        const double an = (a + b) / 2;
        b = std::sqrt(a * b);
        a = an;
    }
    return 4 * (M_PI / (2 * a)) * std::sqrt(l / g);
}

}  // namespace

// The kernel compiles warning-free (-Wall -Wextra -Werror -pedantic) for double and long double,
// and has the parts of runtime/kernel.hpp it should.
BOOST_AUTO_TEST_CASE(constrained_kernel_compiles_cleanly) {
    const auto k = rod_kernel(Stabilization::project);
    BOOST_TEST(k.header.find("n_constraints = 1") != std::string::npos);
    BOOST_TEST(k.header.find("\"lambda_rod\"") != std::string::npos);
    BOOST_TEST(k.header.find("\"reaction_x\"") != std::string::npos);
    eomc::host::CompileRequest c;
    const std::string check = R"(#include "kernel.hpp"
#include <eomc/runtime/kernel.hpp>
namespace rt = eomc::runtime;
using K = eomc::models::)" + k.struct_name + R"(;
static_assert(rt::GeneratedKernel<K> && rt::GeneratedKernel<K, long double>);
static_assert(rt::ConstrainedKernel<K> && rt::ProjectingKernel<K>);
template <class S>
S exercise() {
    const K::Parameters p{};
    S x[K::n_state], dx[K::n_state], J[K::n_state * K::n_state], out[K::n_outputs], res[K::n_constraints];
    S inv[K::n_invariants + 1]{};
    for (int i = 0; i < K::n_state; ++i) x[i] = S(K::initial_state[std::size_t(i)]);
    K::rhs(S(0), x, dx, p);
    K::jacobian(S(0), x, J, p);
    K::outputs(S(0), x, out, p);
    K::invariants(S(0), x, inv, p);
    K::constraint_residuals(S(0), x, res, p);
    K::project(S(0), x, p);
    return dx[0] + J[0] + out[0] + res[0] + inv[0] + x[0];
}
double check() { return exercise<double>() + double(exercise<long double>()); }
)";
    c.files = {{"check.cpp", check}, {"kernel.hpp", k.header}};
    c.flags = {"-c", "-Wall", "-Wextra", "-Werror", "-pedantic"};
    c.suffix = ".o";
    c.what = "the constrained kernel's compile check";
    BOOST_CHECK_NO_THROW(eomc::host::find_or_compile(c, test_support::test_cache_dir));
}

// (a) θ = atan2(x, −y) of the constrained Cartesian run against the polar pendulum over ten
// periods, and (b) λ_rod = −m (l θ̇² + g cos θ)/(2l) (the rod's tension over 2l) along the run.
BOOST_AUTO_TEST_CASE(cartesian_rod_agrees_with_the_polar_pendulum) {
    // A quarter period past the tenth: θ near 0, θ̇ at its largest (a phase error shows in θ there).
    const double rtol = 1e-10, t_end = 10.25 * period();
    auto rc = request(rod_kernel(Stabilization::project), t_end, rtol);
    const fs::path csv = fs::path(EOMC_BINARY_DIR) / "test-output" / "constraints_rod.csv";
    fs::create_directories(csv.parent_path());
    rc.csv_path = csv.string();
    const auto cart = eomc::host::simulate(rc);
    const auto pol = eomc::host::simulate(request(test_support::kernel_of(polar), t_end, rtol));

    const double x = cart.value("x"), y = cart.value("y"), xd = cart.value("x_dot"), yd = cart.value("y_dot");
    const double theta = std::atan2(x, -y), theta_dot = (x * yd - y * xd) / (x * x + y * y);
    // Each accepted step commits a local error of at most ~rtol (relative, the solution's scale
    // max(|θ|, |θ̇|) ≲ 3) and the errors add up at most linearly over the steps of the two runs
    // (the pendulum's phase error grows linearly): |Δθ| ≤ rtol · 3 · (N_cart + N_polar), with a
    // factor 10 for the controller's safety margin.
    const double bound = 10 * rtol * 3 * double(cart.steps + pol.steps);
    BOOST_TEST_MESSAGE("theta: cartesian " << theta << ", polar " << pol.value("theta") << ", |difference| "
                                       << std::abs(theta - pol.value("theta")) << ", bound " << bound);
    BOOST_TEST(std::abs(theta - pol.value("theta")) <= bound);
    BOOST_TEST(std::abs(theta_dot - pol.value("theta_dot")) <= bound * std::sqrt(g / l));

    // λ along the run, from the CSV (t, x, y, x_dot, y_dot, invariants…, outputs…).
    const auto lines = test_support::read_lines(csv);
    BOOST_REQUIRE(lines.size() > 100u);
    const std::string header = lines.front();
    std::vector<std::string> columns;
    for (std::size_t at = 0, next; at <= header.size(); at = next + 1) {
        next = header.find(',', at);
        if (next == std::string::npos) next = header.size();
        columns.push_back(header.substr(at, next - at));
    }
    const auto column = [&](const std::string& name) {
        for (std::size_t i = 0; i < columns.size(); ++i)
            if (columns[i] == name) return i;
        throw std::runtime_error("no column " + name);
    };
    const std::size_t ix = column("x"), iy = column("y"), ixd = column("x_dot"), iyd = column("y_dot"),
                      il = column("lambda_rod"), irx = column("reaction_x");
    double worst = 0;
    for (std::size_t r = 1; r < lines.size(); ++r) {
        const auto v = test_support::csv_numbers(lines[r]);
        const double th = std::atan2(v[ix], -v[iy]);
        const double thd = (v[ix] * v[iyd] - v[iy] * v[ixd]) / (v[ix] * v[ix] + v[iy] * v[iy]);
        const double expected = -m * (l * thd * thd + g * std::cos(th)) / (2 * l);
        worst = std::max(worst, std::abs(v[il] - expected));
        // The generalized reaction on x is λ ∂f/∂x = 2 x λ.
        BOOST_TEST(std::abs(v[irx] - 2 * v[ix] * v[il]) <= 1e-12 * m * g);
    }
    BOOST_TEST_MESSAGE("max |lambda_rod - expected| = " << worst);
    // The rows are integrated states: λ follows them to the run's accuracy (the positions' error
    // ~bound, relative to λ's scale m g / l).
    BOOST_TEST(worst <= 1e-6 * m * g / l);
    BOOST_REQUIRE(cart.constraints.size() == 1u);
    BOOST_TEST(cart.constraints[0].name == "rod");
}

// (c) The rod's residual over 1000 periods, dopri5 at rtol 1e-8: projection keeps it at round-off,
// Baumgarte (α = β = 10) bounded, none lets it grow.
BOOST_AUTO_TEST_CASE(drift_study) {
    const double rtol = 1e-8, t_end = 1000 * period();
    const auto run = [&](Stabilization s, double alpha, double beta) {
        const auto result = eomc::host::simulate(request(rod_kernel(s, alpha, beta), t_end, rtol));
        BOOST_REQUIRE(result.constraints.size() == 1u);
        return result.constraints[0].max_abs_residual;
    };
    const double projected = run(Stabilization::project, 0, 0);
    const double baumgarte = run(Stabilization::baumgarte, 10, 10);
    const double none = run(Stabilization::none, 0, 0);
    std::cout << "drift study over 1000 periods (dopri5, rtol 1e-8): max |x^2 + y^2 - l^2| = " << projected
              << " (project), " << baumgarte << " (baumgarte, alpha = beta = 10), " << none << " (none)\n";
    BOOST_TEST(projected <= 1e-13 * l * l);
    BOOST_TEST(projected < baumgarte);
    BOOST_TEST(baumgarte < none);
}

// The summaries of a constrained run carry the rows; others keep their shape.
BOOST_AUTO_TEST_CASE(summaries_report_the_rows) {
    const auto result = eomc::host::simulate(request(rod_kernel(Stabilization::project), 1.0, 1e-10));
    std::ostringstream text, json;
    eomc::host::print_summary(result, "text", text);
    eomc::host::print_summary(result, "json", json);
    BOOST_TEST(text.str().find("constraints\n") != std::string::npos);
    BOOST_TEST(json.str().find("\"constraints\": {\"rod\": {\"max_abs_residual\": ") != std::string::npos);
}

namespace {

// N particles on a line, masses m_i = 1 + i/N, springs V = Σ k_i x_i²/2 with k_i = i, and the
// centre of mass held: the row Σ m_i x_i = 0, projected after every step.
std::string centre_of_mass_scene(int n) {
    std::string toml = "[scene]\nname = \"centre_held_" + std::to_string(n) + "\"\n[coordinates]\n";
    std::string T, V, row;
    for (int i = 1; i <= n; ++i) {
        const double mass = 1.0 + double(i) / n;
        // Start with x1 = 1, x2 = −m1/m2, the others at rest at 0: the row holds.
        const double x0 = i == 1 ? 1.0 : i == 2 ? -(1.0 + 1.0 / n) / mass : 0.0;
        toml += "x" + std::to_string(i) + " = { initial = " + fmt::format("{:.17g}", x0) + ", rate = 0.0 }\n";
        const std::string m = fmt::format("{:.17g}", mass);
        T += (i > 1 ? " + " : "") + m + "*x" + std::to_string(i) + "_dot^2/2";
        V += (i > 1 ? " + " : "") + std::to_string(i) + "*x" + std::to_string(i) + "^2/2";
        row += (i > 1 ? " + " : "") + m + "*x" + std::to_string(i);
    }
    return toml + "[lagrangian]\nT = \"" + T + "\"\nV = \"" + V + "\"\n[[constraint]]\nname = \"centre\"\nholonomic = \"" +
           row + "\"\nstabilize = \"project\"\n";
}

}  // namespace

// The two ways a kernel solves M u̇ − Wᵀλ = f, W u̇ = r: straight-line code up to 16 coupled
// unknowns (N = 8: 9), the runtime's Schur complement on Eigen past that (N = 20: 21). With
// M = diag(m_i), f_i = −k_i x_i and W = (m_1 … m_N) (a linear row: no bias, and projected, so no
// stabilisation: r = 0), ẍ_i = f_i/m_i + λ and W ẍ = 0 give λ = Σ k_i x_i / Σ m_i at whatever
// state the run reached. Both sides evaluate a few terms per particle, so they differ by round-off:
// 8 N ε times the terms' magnitude over Σ m_i. The projection (position and velocity
// corrections, straight-line or Eigen) keeps the row at the round-off of its terms.
BOOST_AUTO_TEST_CASE(centre_of_mass_held_on_both_solve_paths) {
    for (int n : {8, 20}) {
        const test_support::Kernel k = test_support::kernel_of(centre_of_mass_scene(n));
        const bool straight = k.header.find("W u̇ = r is solved in straight-line") != std::string::npos;
        BOOST_TEST(straight == (n + 1 <= 16), "n = " << n);
        BOOST_TEST((k.header.find("#include <Eigen/Core>") == std::string::npos) == straight, "n = " << n);
        const auto result = eomc::host::simulate(test_support::simulation_request(k, 2.0));
        double sum_kx = 0, total_mass = 0, scale = 0;
        for (int i = 1; i <= n; ++i) {
            const double x = result.value(fmt::format("x{}", i));
            sum_kx += i * x;
            total_mass += 1.0 + double(i) / n;
            scale += std::abs(i * x);
        }
        const double expected = sum_kx / total_mass;
        BOOST_TEST(std::abs(result.value("lambda_centre") - expected) <=
                       8 * n * std::numeric_limits<double>::epsilon() * scale / total_mass,
                   "n = " << n << ": λ = " << result.value("lambda_centre") << ", closed form " << expected);
        // |m_i x_i| ≲ 2: N of them round to well under 1e-12.
        BOOST_REQUIRE(result.constraints.size() == 1u);
        BOOST_TEST(result.constraints[0].max_abs_residual <= 1e-12, "n = " << n);
    }
}
