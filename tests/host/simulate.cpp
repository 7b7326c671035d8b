// eomc simulate end to end: a scene in TOML goes through the whole generator, the emitted
// header is compiled into a cached shared object, integrated, and checked against closed forms.
#define BOOST_TEST_MODULE simulate
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "eomc/runtime/errors.hpp"
#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

#include "csv.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;
using eomc::host::SimulationRequest;
using eomc::host::SimulationResult;
using eomc::host::simulate;

namespace {

const fs::path output_dir = EOMC_BINARY_DIR "/test-output";

// A ball in a smooth tube along x' of a disc turning at Ω about y': q̈ = Ω² q, so
// q(t) = q0 cosh Ωt + (v0/Ω) sinh Ωt. Its Jacobi integral is h = m(q̇² − Ω² q²)/2.
// The parameter `int` is a C++ keyword (the member becomes `int_`): it must still be
// settable by its scene name. Effective angular velocity: Omega*int.
const char* const disk_tube_ball = R"([scene]
name = "disk_tube_ball"

[parameters]
m = 0.5
Omega = 3.0
int = 1.0

[coordinates]
q = { initial = 0.1, rate = 0.0 }

[carrier]
angular_velocity = ["0", "Omega*int", "0"]

[[body]]
name = "ball"
mass = "m"
position = ["q", "0", "0"]
)";

// q̈ = 4q³ from q = 1, q̇ = 0 (a generalized force, so the test does not depend on the sign
// convention for V). Energy q̇²/2 − q⁴ = −1 gives q̇ = √(2(q⁴−1)), and q reaches infinity at
//   t* = ∫₁^∞ dq / √(2(q⁴−1)) = K(1/√2) / 2 = 1.8540746773 / 2 = 0.92703733865,
// well before the end time 2 used below.
const char* const blowup = R"([scene]
name = "blowup"

[coordinates]
q = { initial = 1.0, rate = 0.0 }

[lagrangian]
T = "q_dot^2/2"
V = "0"

[forces]
generalized = { q = "4*q^3" }
)";
constexpr double blowup_time = 0.92703733865;

using test_support::Kernel;

// The whole generator pipeline: scene → model → equations → IR → header.
Kernel generate(const std::string& toml) { return test_support::kernel_of(toml); }

const Kernel& dtb() {
    static const Kernel k = generate(disk_tube_ball);
    return k;
}

SimulationRequest request(const Kernel& k, const std::string& integrator = "dopri5") {
    SimulationRequest r = test_support::simulation_request(k, 1.0);
    r.integrator = integrator;
    r.rtol = 1e-10;
    r.atol = 1e-12;
    r.step = 1e-2;
    return r;
}

struct Closed {
    double q, q_dot;
};
Closed closed_form(double q0, double v0, double omega, double t) {
    return {q0 * std::cosh(omega * t) + v0 / omega * std::sinh(omega * t),
            q0 * omega * std::sinh(omega * t) + v0 * std::cosh(omega * t)};
}

// Global error bound for dopri5 on ẋ = A x, A = [[0, 1], [Ω², 0]], from its own step count.
// An accepted step has error norm ≤ 1, i.e. RMS_i(e_i / sc_i) ≤ 1, so every component of the
// local error estimate is ≤ √n·(atol + rtol·max|x|). Each local error is propagated to t_end by
// exp(A (t_end − t_k)), whose max-norm is ≤ (1 + max(Ω, 1/Ω))·e^{Ω t_end}. The estimate measures
// the embedded 4th-order solution, while the 5th-order one is propagated (local extrapolation),
// so the sum over the steps is a safe bound rather than an estimate — yet a wrong rhs, a
// parameter bound to the wrong member or a broken stepper misses it by orders of magnitude.
double dopri5_bound(const SimulationResult& r, double omega, double x_max, double rtol, double atol) {
    const double n = 2.0;
    return static_cast<double>(r.steps) * std::sqrt(n) * (atol + rtol * x_max) * (1.0 + std::max(omega, 1.0 / omega)) *
           std::exp(omega * r.t);
}

using test_support::read_lines;

// Files in `dir` whose name starts with `prefix` (to find stray temporaries).
std::vector<std::string> files_starting_with(const fs::path& dir, const std::string& prefix) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().rfind(prefix, 0) == 0) out.push_back(e.path().filename().string());
    return out;
}

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::path(EOMC_BINARY_DIR) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

}  // namespace

BOOST_AUTO_TEST_CASE(dopri5_matches_closed_form) {
    const SimulationResult r = simulate(request(dtb()));
    const double omega = 3.0, q0 = 0.1, m = 0.5;
    const Closed exact = closed_form(q0, 0.0, omega, 1.0);
    BOOST_TEST(r.t == 1.0);
    BOOST_TEST(r.steps > 0u);
    const double bound = dopri5_bound(r, omega, std::abs(exact.q_dot), 1e-10, 1e-12);
    BOOST_TEST_INFO("bound " << bound << ", steps " << r.steps);
    BOOST_TEST(std::abs(r.value("q") - exact.q) <= bound);
    BOOST_TEST(std::abs(r.value("q_dot") - exact.q_dot) <= bound);
    BOOST_TEST_MESSAGE("dopri5 error q " << std::abs(r.value("q") - exact.q) << " (bound " << bound << ")");

    // The energy is conserved up to what the state error allows: |dh| ≤ m(|q̇| + Ω²|q|)·|dx|.
    BOOST_REQUIRE(r.invariants.size() == 1u);
    BOOST_TEST(r.invariants[0].name == "energy");
    const double h0 = -0.5 * m * omega * omega * q0 * q0;
    BOOST_TEST(std::abs(r.invariants[0].initial - h0) <= 4 * std::numeric_limits<double>::epsilon() * std::abs(h0));
    BOOST_TEST(r.invariants[0].max_abs_drift <= m * (std::abs(exact.q_dot) + omega * omega * exact.q) * bound);
    BOOST_TEST(r.rhs_evals >= 6 * (r.steps + r.rejected));
}

// RK4 on ẏ = λy multiplies by R(z) = Σ_{k≤4} z^k/k! = e^z − z⁵/120 + O(z⁶) per step (z = λh), so
// after t/h steps y_h(t) = e^{λt}(1 − t λ⁵ h⁴/120 + …). q(t) = (q0/2)(e^{Ωt} + e^{−Ωt}), and
// the growing mode dominates: exact − numerical ≈ (q0/2) e^{Ωt} t Ω⁵ h⁴/120. The neglected
// terms are O(Ωh) = 3 % relative at h = 0.01, hence the 10 % window; halving h must divide
// the error by 2⁴ = 16.
BOOST_AUTO_TEST_CASE(rk4_error_is_the_predicted_h4_term) {
    const double omega = 3.0, q0 = 0.1, t = 1.0;
    const double exact = closed_form(q0, 0.0, omega, t).q;
    double previous = 0.0;
    for (double h : {0.01, 0.005}) {
        SimulationRequest req = request(dtb(), "rk4");
        req.step = h;
        const SimulationResult r = simulate(req);
        BOOST_TEST(r.steps == static_cast<std::size_t>(std::lround(t / h)));
        BOOST_TEST(r.rhs_evals == 4 * r.steps);
        const double error = exact - r.value("q");
        const double predicted = q0 / 2 * std::exp(omega * t) * t * std::pow(omega, 5) * std::pow(h, 4) / 120;
        BOOST_TEST_INFO("h " << h << " error " << error << " predicted " << predicted);
        BOOST_TEST(error / predicted >= 0.9);
        BOOST_TEST(error / predicted <= 1.1);
        if (previous != 0.0) {
            BOOST_TEST(previous / error >= 15.0);
            BOOST_TEST(previous / error <= 17.0);
        }
        previous = error;
    }
}

BOOST_AUTO_TEST_CASE(overrides_change_the_result_as_the_closed_form_says) {
    SimulationRequest req = request(dtb());
    // `int` is a C++ keyword: set by its scene name, it lands in member `int_` by position.
    req.overrides = {{"Omega", 1.0}, {"int", 2.0}, {"q", 0.2}, {"q_dot", 0.3}, {"m", 2.0}};
    const SimulationResult r = simulate(req);
    const double omega = 2.0;
    const Closed exact = closed_form(0.2, 0.3, omega, 1.0);
    const double bound = dopri5_bound(r, omega, std::abs(exact.q_dot), 1e-10, 1e-12);
    BOOST_TEST(std::abs(r.value("q") - exact.q) <= bound);
    BOOST_TEST(std::abs(r.value("q_dot") - exact.q_dot) <= bound);
    BOOST_TEST(r.invariants.at(0).initial == 0.5 * 2.0 * (0.3 * 0.3 - omega * omega * 0.2 * 0.2),
               boost::test_tools::tolerance(1e-14));
    BOOST_REQUIRE(r.parameters.size() == 3u);
    BOOST_TEST(r.parameters[0].first == "m");
    BOOST_TEST(r.parameters[0].second == 2.0);
    BOOST_TEST(r.parameters[2].first == "int");
    BOOST_TEST(r.parameters[2].second == 2.0);
}

BOOST_AUTO_TEST_CASE(unknown_override_names_the_nearest_one) {
    for (const auto& [typo, nearest] : std::vector<std::pair<std::string, std::string>>{{"Omege", "Omega"},
                                                                                         {"q_do", "q_dot"}}) {
        SimulationRequest req = request(dtb());
        req.overrides = {{typo, 1.0}};
        try {
            simulate(req);
            BOOST_ERROR("no InputError for --set " << typo);
        } catch (const eomc::InputError& e) {
            BOOST_TEST_INFO(e.what());
            BOOST_TEST(e.where().file == "--set");
            BOOST_TEST(e.message().find("did you mean '" + nearest + "'") != std::string::npos);
        }
    }
    // Nothing close: no suggestion, but the known names are listed.
    SimulationRequest req = request(dtb());
    req.overrides = {{"zzzzzz", 1.0}};
    try {
        simulate(req);
        BOOST_ERROR("no InputError for --set zzzzzz");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.message().find("did you mean") == std::string::npos);
        BOOST_TEST(e.message().find("parameters: m, Omega, int; initial values: q, q_dot") != std::string::npos,
                   e.message());
    }
}

BOOST_AUTO_TEST_CASE(bad_settings_are_input_errors) {
    SimulationRequest req = request(dtb(), "rk5");
    try {
        simulate(req);
        BOOST_ERROR("no InputError for integrator rk5");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.message().find("did you mean 'rk4'") != std::string::npos, e.message());
    }
    req = request(dtb(), "rk4");
    req.step = 0.0;
    BOOST_CHECK_THROW(simulate(req), eomc::InputError);
    req = request(dtb());
    req.t_end = -1.0;
    BOOST_CHECK_THROW(simulate(req), eomc::InputError);
    req = request(dtb());
    req.summary_format = "yaml";
    BOOST_CHECK_THROW(simulate(req), eomc::InputError);
}

BOOST_AUTO_TEST_CASE(csv_has_header_and_one_row_per_accepted_step) {
    fs::create_directories(output_dir);
    for (const std::string integrator : {"dopri5", "rk4"}) {
        const fs::path csv = output_dir / ("dtb-" + integrator + ".csv");
        fs::remove(csv);
        SimulationRequest req = request(dtb(), integrator);
        req.csv_path = csv.string();
        const SimulationResult r = simulate(req);
        const auto lines = read_lines(csv);
        BOOST_REQUIRE(lines.size() >= 2u);
        BOOST_TEST(lines[0] == "t,q,q_dot,energy,holding_force_1,holding_force_2,holding_force_3,holding_moment_1,"
                               "holding_moment_2,holding_moment_3");
        BOOST_TEST(lines.size() - 1 == r.steps + 1);  // t = 0 and every accepted step
        BOOST_TEST(r.csv_rows == r.steps + 1);
        const auto first = test_support::csv_numbers(lines[1]), last = test_support::csv_numbers(lines.back());
        BOOST_REQUIRE(first.size() == 10u);  // t, q, q_dot, energy and the six holding outputs
        BOOST_TEST(first[0] == 0.0);
        BOOST_TEST(first[1] == 0.1);
        BOOST_TEST(first[2] == 0.0);
        // %.17g round-trips: the last row is bit-for-bit the final state.
        BOOST_TEST(last[0] == 1.0);
        BOOST_TEST(last[1] == r.value("q"));
        BOOST_TEST(last[2] == r.value("q_dot"));
        BOOST_TEST(files_starting_with(output_dir, csv.filename().string() + ".tmp").empty());
    }
}

BOOST_AUTO_TEST_CASE(second_run_is_a_cache_hit) {
    SimulationRequest req = request(dtb());
    req.cache_dir = fresh_dir("test-cache-fresh").string();
    const SimulationResult first = simulate(req);
    const SimulationResult second = simulate(req);
    BOOST_TEST(!first.cache_hit);
    BOOST_TEST(second.cache_hit);
    BOOST_TEST(second.library_path == first.library_path);
    BOOST_TEST(second.value("q") == first.value("q"));
    BOOST_TEST_MESSAGE("kernel compile " << first.compile_s << " s, cache hit " << second.compile_s << " s");
    // Only the finished library is in the cache: no temporaries left behind.
    std::vector<std::string> entries;
    for (const auto& e : fs::directory_iterator(req.cache_dir)) entries.push_back(e.path().filename().string());
    BOOST_REQUIRE(entries.size() == 1u);
    BOOST_TEST(entries[0] == eomc::host::cache_key(dtb().header, dtb().struct_name) + ".so");
}

BOOST_AUTO_TEST_CASE(concurrent_first_runs_share_the_cache_safely) {
    SimulationRequest req = request(dtb());
    req.cache_dir = fresh_dir("test-cache-concurrent").string();
    std::vector<double> q(3, 0.0);
    std::vector<std::string> errors(3);
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < q.size(); ++i)
        threads.emplace_back([&, i] {
            try {
                q[i] = simulate(req).value("q");
            } catch (const std::exception& e) {
                errors[i] = e.what();
            }
        });
    for (auto& t : threads) t.join();
    for (std::size_t i = 0; i < q.size(); ++i) {
        BOOST_TEST(errors[i].empty(), errors[i]);
        BOOST_TEST(q[i] == q[0]);
    }
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(req.cache_dir)) ++entries;
    BOOST_TEST(entries == 1u);
}

BOOST_AUTO_TEST_CASE(compile_failure_reports_the_compiler_output) {
    SimulationRequest req = request(dtb());
    req.header_text = "namespace eomc::models { struct DiskTubeBall { this is not C++; }; }\n";
    req.cache_dir = fresh_dir("test-cache-broken").string();
    try {
        simulate(req);
        BOOST_ERROR("no error for a header that does not compile");
    } catch (const eomc::InputError&) {
        BOOST_ERROR("a compile failure is not an input error");
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        BOOST_TEST(what.find("compiling the generated kernel failed") != std::string::npos, what);
        BOOST_TEST(what.find("error") != std::string::npos, what);
        BOOST_TEST(what.find("kernel.hpp") != std::string::npos, what);
    }
    BOOST_TEST(fs::is_empty(req.cache_dir));  // no partial library
}

BOOST_AUTO_TEST_CASE(failed_integration_keeps_the_csv_up_to_the_failure) {
    const Kernel k = generate(blowup);
    fs::create_directories(output_dir);
    for (const std::string integrator : {"dopri5", "rk4"}) {
        const fs::path csv = output_dir / ("blowup-" + integrator + ".csv");
        fs::remove(csv);
        SimulationRequest req = request(k, integrator);
        req.t_end = 2.0;  // > t* ≈ 0.927
        req.step = 1e-3;
        req.csv_path = csv.string();
        try {
            simulate(req);
            BOOST_ERROR(integrator << ": no IntegrationError for a solution that blows up at t ≈ 0.927");
        } catch (const eomc::runtime::IntegrationError& e) {
            BOOST_TEST_MESSAGE(integrator << ": " << e.what());
            // It stopped at the singularity, not somewhere else. dopri5 creeps up to t* with ever
            // smaller steps; rk4's fixed steps overshoot it by a few steps before overflowing.
            BOOST_TEST(e.t() <= blowup_time + (integrator == "rk4" ? 5 * req.step : 0.0));
            BOOST_TEST(e.t() >= 0.9 * blowup_time);
            BOOST_TEST(std::string(e.what()).find("blowup") != std::string::npos);
            BOOST_TEST(std::string(e.what()).find(csv.string() + " holds the ") != std::string::npos, e.what());
        }
        // The CSV holds the trajectory up to the last accepted state, every row complete and
        // finite, and no temporary is left beside it.
        const auto lines = read_lines(csv);
        BOOST_TEST_REQUIRE(lines.size() > 2u);
        BOOST_TEST(lines.front().rfind("t,q,q_dot", 0) == 0u);
        double t_previous = -1;
        for (std::size_t i = 1; i < lines.size(); ++i) {
            std::stringstream row(lines[i]);
            std::string cell;
            std::getline(row, cell, ',');
            const double t = std::stod(cell);
            BOOST_TEST(t > t_previous);
            t_previous = t;
            while (std::getline(row, cell, ',')) BOOST_TEST(std::isfinite(std::stod(cell)), lines[i]);
        }
        BOOST_TEST(t_previous <= blowup_time + (integrator == "rk4" ? 5 * req.step : 0.0));
        BOOST_TEST(files_starting_with(output_dir, csv.filename().string()) == std::vector<std::string>{csv.filename().string()},
                   boost::test_tools::per_element());
    }
}

BOOST_AUTO_TEST_CASE(json_summary) {
    SimulationResult r;
    r.t = 1.0;
    r.state = {{"q", 0.1}, {"q_dot", std::nan("")}};
    r.invariants = {{"energy", -0.25, -0.25, 1e-17}};
    r.steps = 10;
    r.rejected = 1;
    r.rhs_evals = 67;
    r.wall_s = 0.5;
    r.compile_s = std::numeric_limits<double>::infinity();
    r.cache_hit = true;
    r.events = {{"wall", 0.75, -1, true, {0.5, -2.0}}};
    r.stopped_by = "wall";
    r.compensated = true;
    std::ostringstream out;
    eomc::host::print_summary(r, "json", out);
    BOOST_TEST(out.str() ==
               "{\"t\": 1, \"state\": {\"q\": 0.10000000000000001, \"q_dot\": null}, \"outputs\": {}, \"invariants\": {\"energy\": "
               "{\"initial\": -0.25, \"max_abs_drift\": 1.0000000000000001e-17}}, \"events\": [{\"name\": \"wall\", "
               "\"t\": 0.75, \"direction\": \"down\", \"terminal\": true, \"state\": {\"q\": 0.5, \"q_dot\": -2}}], "
               "\"stopped_by\": \"wall\", \"compensated\": true, \"steps\": 10, \"rejected\": 1, "
               "\"rhs_evals\": 67, \"wall_s\": 0.5, \"compile_s\": null, \"cache_hit\": true}\n");
}

BOOST_AUTO_TEST_CASE(text_summary) {
    const SimulationResult r = simulate(request(dtb()));
    std::ostringstream out;
    eomc::host::print_summary(r, "text", out);
    const std::string s = out.str();
    BOOST_TEST_MESSAGE(s);
    for (const std::string fragment : {"disk_tube_ball: dopri5 (rtol 1e-10, atol 1e-12) to t = 1", "q_dot", "energy",
                                       "max |drift|", "accepted", "rhs evaluations", "integration"})
        BOOST_TEST(s.find(fragment) != std::string::npos, "missing '" << fragment << "' in\n" << s);
}

// A free carrier's attitude quaternion is put back on |e| = 1 after every accepted step (the
// kernel's project(), called by the runtime's drivers), so the run ends on the unit sphere to
// the rounding of one normalisation (a square root and a division: 4 ulp), whatever the
// tolerance (tests/runtime/adaptive.cpp shows the drift a run without projection has).
BOOST_AUTO_TEST_CASE(free_carrier_quaternion_stays_unit) {
    const Kernel k = generate(test_support::bundled_scene("free_disk_tube_ball"));
    for (const char* integrator : {"dopri5", "rk4", "gl4"}) {
        SimulationRequest req = request(k, integrator);
        req.t_end = 20.0;
        req.rtol = req.atol = 1e-6;
        req.step = 1e-2;
        const SimulationResult r = simulate(req);
        const double e0 = r.value("carrier_e0"), e1 = r.value("carrier_e1"), e2 = r.value("carrier_e2"),
                     e3 = r.value("carrier_e3");
        const double norm = std::sqrt(e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3);
        BOOST_TEST(std::abs(norm - 1) <= 4 * std::numeric_limits<double>::epsilon(), integrator << ": |e| = " << norm);
        BOOST_TEST(std::abs(e0) < 1.0);  // it did turn: the check is not on the initial (1, 0, 0, 0)
    }
}
