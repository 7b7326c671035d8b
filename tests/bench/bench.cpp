// eomc bench: the driver's rows (every method, on a hand-written separable kernel), and the
// command as a user meets it: the CSV with its documented columns, errors that fall as the
// tolerance tightens and stay within bounds derived from the method, odeint's rows beside ours,
// the plot, the closed-form and the float128 reference agreeing, bad input refused with exit 2
// and nothing written. No test depends on timings.
#define BOOST_TEST_MODULE bench
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "oscillator.hpp"

namespace fs = std::filesystem;

namespace {

const std::string header =
    "method,library,kind,setting,error,max_invariant_drift,rhs_evals,steps,rejected,wall_seconds,repetitions";

using test_support::Result;
using test_support::slurp;

fs::path scratch(const std::string& name) { return test_support::scratch("bench-scratch", name); }

// Compiled drivers are kept here across runs of the suite (keyed by content, so never stale).
std::string cache_dir() { return (fs::path(EOMC_BINARY_DIR) / "bench-cache").string(); }

Result run(const std::string& command, const fs::path& dir, const std::string& env = "") {
    return test_support::run_command(command, dir, env);
}

struct Row {
    std::string method, library, kind;
    double setting = 0, error = 0, drift = 0, seconds = 0;
    long evals = 0, steps = 0, rejected = 0, repetitions = 0;
};

std::vector<std::string> split(const std::string& s, char c) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, c);) out.push_back(item);
    if (!s.empty() && s.back() == c) out.emplace_back();
    return out;
}

// Rows of a CSV in the driver's format (notes, lines starting with '#', skipped); the header is checked.
std::vector<Row> parse_csv(const std::string& text) {
    std::vector<Row> rows;
    std::stringstream in(text);
    bool seen_header = false;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        if (!seen_header) {
            BOOST_TEST(line == header);
            seen_header = true;
            continue;
        }
        const auto f = split(line, ',');
        BOOST_REQUIRE_MESSAGE(f.size() == 11u, "row with " << f.size() << " fields: " << line);
        Row r;
        r.method = f[0];
        r.library = f[1];
        r.kind = f[2];
        r.setting = std::stod(f[3]);
        r.error = std::stod(f[4]);
        r.drift = f[5].empty() ? NAN : std::stod(f[5]);
        r.evals = std::stol(f[6]);
        r.steps = std::stol(f[7]);
        r.rejected = std::stol(f[8]);
        r.seconds = std::stod(f[9]);
        r.repetitions = std::stol(f[10]);
        rows.push_back(r);
    }
    BOOST_TEST(seen_header);
    return rows;
}

const std::string orbit_header =
    "formulation,method,library,kind,setting,position_error,max_invariant_drift,rhs_evals,steps,rejected,"
    "wall_seconds,repetitions";

// Rows of a formulation bench's CSV (header checked: an orbit's unless given), keyed by
// formulation and then method.
std::map<std::string, std::map<std::string, std::vector<Row>>> parse_orbit_csv(const std::string& text,
                                                                               const std::string& expected = orbit_header) {
    std::map<std::string, std::map<std::string, std::vector<Row>>> out;
    std::stringstream in(text);
    std::string line;
    std::getline(in, line);
    BOOST_TEST(line == expected);
    for (; std::getline(in, line);) {
        const auto comma = line.find(',');
        BOOST_REQUIRE(comma != std::string::npos);
        // The rest is a driver row: parse it as one under the driver's header.
        for (const Row& r : parse_csv(header + "\n" + line.substr(comma + 1) + "\n"))
            out[line.substr(0, comma)][r.method].push_back(r);
    }
    return out;
}

std::map<std::string, std::vector<Row>> by_method(const std::vector<Row>& rows) {
    std::map<std::string, std::vector<Row>> m;
    for (const auto& r : rows) m[r.method].push_back(r);
    return m;
}

// Each tighter tolerance (rows in sweep order, tolerances decreasing) gives a smaller error.
void check_errors_fall(const std::string& method, const std::vector<Row>& rows) {
    for (std::size_t i = 1; i < rows.size(); ++i) {
        BOOST_TEST(rows[i].setting < rows[i - 1].setting);
        BOOST_TEST(rows[i].error < rows[i - 1].error, method << ": error " << rows[i].error << " at tol " << rows[i].setting
                                                             << " not below " << rows[i - 1].error << " at "
                                                             << rows[i - 1].setting);
    }
}

double observed_order(const std::vector<Row>& rows) {
    BOOST_REQUIRE(rows.size() == 2u);
    return std::log(rows[0].error / rows[1].error) / std::log(rows[1].setting / rows[0].setting);
}

const std::string oscillator_scene = test_support::oscillator_scene({.name = "bench_oscillator",
                                                                      .summary_line = "summary = \"q'' = -w^2 q, closed form\"",
                                                                      .parameter = "w",
                                                                      .value = "2.0",
                                                                      .stiffness = "w^2",
                                                                      .tail = "[simulate]\nt_end = 3.0\n"});

const char* oscillator_reference = R"toml([reference]
q = "cos(w*t)"
q_dot = "-w*sin(w*t)"
)toml";

using test_support::write_scene;

std::string eomc_bench(const fs::path& scene, const fs::path& out, const std::string& options) {
    return std::string(EOMC_EXECUTABLE) + " bench '" + scene.string() + "' -o '" + out.string() + "' --cache-dir '" +
           cache_dir() + "' --min-time 0 --repeats 1 " + options;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The driver on the hand-written circular Kepler orbit (tests/bench/driver): one period, exact
// solution (cos t, sin t, -sin t, cos t).
// ---------------------------------------------------------------------------------------------
BOOST_AUTO_TEST_CASE(driver_runs_every_method) {
    const fs::path dir = scratch("driver");
    const Result r = run(std::string(BENCH_DRIVER_CHECK) +
                             " --t-end 6.283185307179586 --tolerances 1e-5,1e-8,1e-11 --steps 128,256 "
                             "--min-time 1e-9 --repeats 2",
                         dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("# reference: closed form (tests/bench/driver/bench_config.hpp)") != std::string::npos);
    const auto rows = by_method(parse_csv(r.out));
    const std::set<std::string> expected{"rk4", "dopri5", "dop853", "radau5", "gl4", "gl6", "gl8", "verlet", "yoshida6", "kahanli8",
                                         "runge_kutta_dopri5", "runge_kutta_fehlberg78", "bulirsch_stoer",
                                         "symplectic_rkn_sb3a_mclachlan"};
    for (const auto& m : expected) BOOST_TEST(rows.count(m) == 1u, "no rows for " << m);
    BOOST_TEST(rows.size() == expected.size());

    for (const auto& [method, list] : rows) {
        BOOST_TEST_CONTEXT(method) {
            BOOST_TEST(list.front().library == (method.find('_') == std::string::npos ? "eomc" : "odeint"));
            for (const Row& row : list) {
                BOOST_TEST(row.repetitions >= 2);
                BOOST_TEST(row.seconds > 0.0);
                BOOST_TEST(std::isfinite(row.drift));  // the kernel has two invariants
            }
            if (list.front().kind == "tolerance") {
                BOOST_TEST(list.size() == 3u);
                check_errors_fall(method, list);
            } else {
                BOOST_TEST(list.size() == 2u);
                for (const Row& row : list) BOOST_TEST(row.steps == static_cast<long>(row.setting));
            }
        }
    }

    // The counting wrapper sees exactly the calls each method makes per step: RK4 4; splitting
    // methods s per step plus one start-up call (first same as last: Verlet s = 1, Yoshida 7,
    // Kahan-Li 15); McLachlan's SB3A 6 per step (no FSAL in odeint); DOP853 without dense output
    // 12 per accepted and 11 per rejected attempt plus f(t0) and the starting-step probe; Fehlberg
    // 7(8) 13 per attempt plus the same two (odeint starts from the step our runtime would choose);
    // odeint's Dormand-Prince 6 per attempt plus those two and its own first f(t0).
    const auto per_step = [&](const char* m, long per, long extra) {
        for (const Row& row : rows.at(m)) BOOST_TEST(row.evals == per * row.steps + extra, m << " at " << row.setting);
    };
    per_step("rk4", 4, 0);
    per_step("verlet", 1, 1);
    per_step("yoshida6", 7, 1);
    per_step("kahanli8", 15, 1);
    per_step("symplectic_rkn_sb3a_mclachlan", 6, 0);
    for (const Row& row : rows.at("dop853")) BOOST_TEST(row.evals == 2 + 12 * row.steps + 11 * row.rejected);
    for (const Row& row : rows.at("runge_kutta_fehlberg78")) BOOST_TEST(row.evals == 2 + 13 * (row.steps + row.rejected));
    for (const Row& row : rows.at("runge_kutta_dopri5")) BOOST_TEST(row.evals == 3 + 6 * (row.steps + row.rejected));

    // Orders from 128 to 256 steps, where these methods are in their asymptotic regime (errors
    // 1e-5 .. 1e-13, far above round-off): within 0.3 of the theory (the next term of the error
    // expansion shifts the ratio by O(h), h = 2 pi / 128 = 0.05).
    const std::map<std::string, double> orders{{"rk4", 4}, {"gl4", 4}, {"gl6", 6}, {"verlet", 2},
                                               {"yoshida6", 6}, {"symplectic_rkn_sb3a_mclachlan", 4}};
    for (const auto& [m, p] : orders) {
        const double q = observed_order(rows.at(m));
        BOOST_TEST(std::abs(q - p) <= 0.3, m << ": observed order " << q << ", expected " << p);
    }

    // Adaptive error bound. On the circular orbit a local error d changes the energy by <= (|v| +
    // 1/r^2) d = 2 d, the semi-major axis by 2 a^2 dE = 4 d, the mean motion by 1.5 * 4 d = 6 d,
    // hence the phase at the end by 6 d T = 38 d and the state (speed 1) by as much; plus d itself.
    // Each accepted step's local error is held to the tolerance weight sc <= atol + rtol * 1 = 2 tol
    // per component. Bound: 39 * 2 tol * accepted steps.
    for (const char* m : {"dopri5", "dop853"})
        for (const Row& row : rows.at(m))
            BOOST_TEST(row.error <= 78.0 * row.setting * static_cast<double>(row.steps),
                       m << " tol " << row.setting << ": error " << row.error);
}

// ---------------------------------------------------------------------------------------------
// eomc bench on a generated kernel (harmonic oscillator, closed form): CSV, table, plot.
// ---------------------------------------------------------------------------------------------
BOOST_AUTO_TEST_CASE(bench_writes_csv_table_and_plot) {
    const fs::path dir = scratch("oscillator");
    const fs::path scene = write_scene(dir, std::string(oscillator_scene) + oscillator_reference);
    const fs::path out = dir / "out";
    const Result r = run(eomc_bench(scene, out,
                                    "--methods dop853,dopri5,rk4,gl6,verlet,runge_kutta_dopri5,runge_kutta_fehlberg78,"
                                    "bulirsch_stoer --tolerances 1e-4,1e-7,1e-10 --steps 64,256"),
                         dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string csv = slurp(out / "work_precision.csv");
    BOOST_TEST(csv.substr(0, header.size() + 1) == header + "\n");
    BOOST_TEST(csv.find('#') == std::string::npos);  // notes go to the table, not into the data
    const auto rows = by_method(parse_csv(csv));
    BOOST_TEST(rows.size() == 8u);
    // T = q_dot^2/2 with V(q): separable, so the generated kernel has acceleration() and Verlet runs.
    // Verlet turns (q, q_dot) by the angle w~ h with cos(w~ h) = 1 - (wh)^2/2, so the phase lags
    // by t (w~ - w) = t w^3 h^2 / 24 + O(h^4), and the velocity's amplitude is off by (wh)^2/8: in
    // the max norm (the velocity's amplitude is w) the error is w (t w^3 h^2/24 + (wh)^2/8), to
    // within the O(h^4) terms ((wh)^2 <= 0.009 here, so 10% covers them). Order 2: the two step
    // counts' errors differ by 16 to the same 10%.
    BOOST_TEST_REQUIRE(rows.count("verlet") == 1u);
    BOOST_TEST_REQUIRE(rows.at("verlet").size() == 2u);
    for (const Row& row : rows.at("verlet")) {
        const double w = 2, t = 3, h = row.setting;
        BOOST_TEST(row.error <= 1.1 * w * (t * w * w * w * h * h / 24 + w * w * h * h / 8), "verlet h " << h);
    }
    BOOST_TEST(std::abs(observed_order(rows.at("verlet")) - 2.0) < std::log(1.1) / std::log(4.0));
    BOOST_TEST(r.out.find("note: reference: closed form ([reference] of") != std::string::npos, r.out);
    for (const char* m : {"runge_kutta_dopri5", "runge_kutta_fehlberg78", "bulirsch_stoer"}) {
        BOOST_TEST_REQUIRE(rows.count(m) == 1u, m);
        BOOST_TEST(rows.at(m).front().library == "odeint");
        BOOST_TEST(r.out.find(m) != std::string::npos, "table lacks " << m);
    }
    for (const char* m : {"dop853", "dopri5", "runge_kutta_dopri5", "runge_kutta_fehlberg78", "bulirsch_stoer"}) {
        BOOST_TEST_REQUIRE(rows.at(m).size() == 3u, m);
        check_errors_fall(m, rows.at(m));
    }
    // q'' = -w^2 q is a rotation in (q, q_dot / w): errors are carried along without growth in
    // that norm, and converting back and forth costs at most a factor w * sqrt(2) = 2.9 in the
    // max norm. Local errors are held to sc <= atol + rtol * max|x| <= 3 tol. Bound: 3 * 2.9 * tol
    // per accepted step.
    for (const char* m : {"dop853", "dopri5"})
        for (const Row& row : rows.at(m))
            BOOST_TEST(row.error <= 8.7 * row.setting * static_cast<double>(row.steps), m << " tol " << row.setting);
    // The energy is the kernel's one invariant: its drift is reported, and the symmetric gl6 keeps
    // it to round-off-level oscillations (< 1e-10 at 256 steps, where RK4 drifts visibly).
    BOOST_TEST(rows.at("gl6").back().drift < 1e-10);
    BOOST_TEST(rows.at("rk4").back().drift > rows.at("gl6").back().drift);
    if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
        const std::string png = slurp(out / "work_precision.png");
        BOOST_TEST(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
        BOOST_TEST(r.out.find("plot: ") != std::string::npos);
    }

    // Without gnuplot: the same CSV, a warning, exit 0.
    const fs::path out2 = dir / "out2";
    const Result no_plot =
        run(eomc_bench(scene, out2, "--methods dop853 --tolerances 1e-6"), dir, "EOMC_GNUPLOT=/nonexistent/gnuplot");
    BOOST_TEST_REQUIRE(no_plot.status == 0, no_plot.err);
    BOOST_TEST(no_plot.err.find("gnuplot was not found") != std::string::npos, no_plot.err);
    BOOST_TEST(fs::exists(out2 / "work_precision.csv"));
    BOOST_TEST(!fs::exists(out2 / "work_precision.png"));
}

// Without [reference] the errors are measured against a float128 DOP853 run. The double runs
// are the same as with the closed form (same kernel, same settings), so the two errors differ by
// no more than the two references do: the float128 run's own error, below 1e-20.
BOOST_AUTO_TEST_CASE(float128_reference_agrees_with_closed_form) {
    const fs::path dir = scratch("float128");
    const fs::path closed = write_scene(dir, std::string(oscillator_scene) + oscillator_reference);
    const Result a = run(eomc_bench(closed, dir / "closed", "--methods dop853,rk4 --tolerances 1e-5,1e-9 --steps 100"), dir);
    BOOST_TEST_REQUIRE(a.status == 0, a.err);
    const fs::path numeric = write_scene(dir, oscillator_scene);
    const Result b = run(eomc_bench(numeric, dir / "numeric", "--methods dop853,rk4 --tolerances 1e-5,1e-9 --steps 100"), dir);
    BOOST_TEST_REQUIRE(b.status == 0, b.err);
    BOOST_TEST(b.out.find("note: reference: float128 DOP853 at rtol = atol = 1e-26") != std::string::npos, b.out);
    const auto ra = parse_csv(slurp(dir / "closed" / "work_precision.csv"));
    const auto rb = parse_csv(slurp(dir / "numeric" / "work_precision.csv"));
    BOOST_TEST_REQUIRE(ra.size() == 3u);
    BOOST_TEST_REQUIRE(rb.size() == ra.size());
    for (std::size_t i = 0; i < ra.size(); ++i) {
        BOOST_TEST(ra[i].method == rb[i].method);
        BOOST_TEST(ra[i].evals == rb[i].evals);
        BOOST_TEST(std::abs(ra[i].error - rb[i].error) <= 1e-20, ra[i].method << ": " << ra[i].error << " vs " << rb[i].error);
    }
}

// A run (the reference's too) stops once its pace projects it past --budget-s (issue 29): --t-end
// 1e300 computed a float128 reference for minutes before it failed. Now it is refused after 2 s
// with the projection. (A double run of a method on this small kernel meets the runtime's budget
// of 10^7 steps sooner; on a larger one the projection stops it, as a note.)
BOOST_AUTO_TEST_CASE(a_run_past_its_budget_stops_with_its_projection) {
    const fs::path dir = scratch("budget");
    const fs::path numeric = write_scene(dir, oscillator_scene);  // the float128 reference
    const Result r = run(eomc_bench(numeric, dir / "numeric", "--methods dop853 --tolerances 1e-6 --t-end 1e300 --budget-s 100"),
                   dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("the reference run failed: at its pace over the first") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("more than the budget of 100 s (--budget-s)") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "numeric" / "work_precision.csv"));
}

// ---------------------------------------------------------------------------------------------
// Bad input: exit 2, a message that names the problem, nothing written.
// ---------------------------------------------------------------------------------------------
BOOST_AUTO_TEST_CASE(bad_input_exits_2_and_writes_nothing) {
    const fs::path dir = scratch("bad");
    const fs::path scene = write_scene(dir, std::string(oscillator_scene) + oscillator_reference);
    const fs::path out = dir / "out";

    Result r = run(eomc_bench(scene, out, "--methods dop853,dop835"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--methods: error: unknown method 'dop835'; did you mean 'dop853'?") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(out));

    r = run(eomc_bench(scene, out, "--tolerances 1e-6,2"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--tolerances: error: a tolerance must lie in (0, 1), not 2") != std::string::npos, r.err);
    r = run(eomc_bench(scene, out, "--steps 10,abc"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("'abc' is not a number") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(out));

    // A reference must be a function of t and the parameters: the coordinate is pointed at.
    const fs::path bad = write_scene(dir, std::string(oscillator_scene) + "[reference]\nq = \"cos(w*t)\"\nq_dot = \"-w*q\"\n");
    r = run(eomc_bench(bad, out, ""), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("scene.toml:15:13: error: 'q' is a coordinate, which may not appear in the reference value of "
                          "'q_dot'") != std::string::npos,
               r.err);
    BOOST_TEST(!fs::exists(out));
}

// ---------------------------------------------------------------------------------------------
// Orbit scenes: the formulation axis. Two revolutions of scenes/leo_j2.toml (a = 7000 km,
// e = 0.01, period 5828.5 s), Cowell and equinoctial, each judged by its position at t_end
// against a float128 Cowell run.
// ---------------------------------------------------------------------------------------------
namespace {

const std::string leo_j2 = std::string(EOMC_SOURCE_DIR) + "/scenes/leo_j2.toml";
const char* orbit_sweep = "--t-end 11657 --formulations cowell,equinoctial --methods dop853,dopri5,rk4 "
                          "--tolerances 1e-6,1e-8,1e-10 --steps 800,1600";

}  // namespace

BOOST_AUTO_TEST_CASE(orbit_formulations_axis) {
    const fs::path dir = scratch("orbit");
    const Result r = run(eomc_bench(leo_j2, dir / "out", orbit_sweep), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto rows = parse_orbit_csv(slurp(dir / "out" / "work_precision.csv"));
    BOOST_TEST(rows.size() == 2u);
    BOOST_TEST(r.out.find("note: reference: leo_j2_cowell in float128 (113-bit), DOP853 at rtol = atol = 1e-26") !=
                   std::string::npos,
               r.out);
    BOOST_TEST(r.out.find("times below the smallest error measured") != std::string::npos, r.out);
    if (std::system("command -v gnuplot > /dev/null 2>&1") == 0)
        BOOST_TEST(slurp(dir / "out" / "work_precision.png").substr(0, 4) == std::string("\x89PNG", 4));

    for (const char* formulation : {"cowell", "equinoctial"}) {
        BOOST_TEST_CONTEXT(formulation) {
            BOOST_TEST_REQUIRE(rows.count(formulation) == 1u);
            const auto& methods = rows.at(formulation);
            BOOST_TEST(methods.size() == 3u);
            BOOST_TEST(r.out.find(std::string(formulation) + " ") != std::string::npos, "table lacks " << formulation);
            for (const char* m : {"dop853", "dopri5"}) {
                BOOST_TEST_REQUIRE(methods.count(m) == 1u, m);
                const auto& list = methods.at(m);
                BOOST_TEST_REQUIRE(list.size() == 3u, m);
                check_errors_fall(m, list);
                // An error-per-step controller with local extrapolation (both pairs advance with the
                // higher order) makes the global error proportional to the tolerance (HNW II.4):
                // over these four decades the error must fall by 10^(4 +- 1), i.e. a slope within
                // 0.75 .. 1.25 (measured 1.0 .. 1.1).
                const double slope =
                    std::log(list.front().error / list.back().error) / std::log(list.front().setting / list.back().setting);
                BOOST_TEST((slope >= 0.75 && slope <= 1.25), m << ": error slope " << slope << " against the tolerance");
            }
            // RK4 from 800 to 1600 steps (h = 14.6 .. 7.3 s, n h <= 0.016 rad): order 4 within 0.3,
            // as for the Kepler orbit above.
            BOOST_TEST_REQUIRE(methods.count("rk4") == 1u);
            const double q = observed_order(methods.at("rk4"));
            BOOST_TEST(std::abs(q - 4.0) <= 0.3, "rk4: observed order " << q);
        }
    }

    // The same runs against a reference at another tolerance (a second float128 run, cached
    // separately): the double runs are deterministic, so each error moves by no more than the
    // two references differ, which is at most the sum of their spreads (each bounds its own
    // reference's error; the looser one's is the larger, reported in its note).
    const Result b = run(eomc_bench(leo_j2, dir / "out2", std::string(orbit_sweep) + " --reference-tolerance 1e-22"), dir);
    BOOST_TEST_REQUIRE(b.status == 0, b.err);
    const auto spread_of = [](const std::string& out) {
        const std::string key = "away in (x, y, z)";
        const auto end = out.find(key);
        BOOST_REQUIRE(end != std::string::npos);
        const auto start = out.rfind(" ends ", end);
        return std::stod(out.substr(start + 6, end - start - 7));
    };
    const double tolerance = spread_of(r.out) + spread_of(b.out);
    BOOST_TEST(tolerance < 1e-12);
    const auto rows2 = parse_orbit_csv(slurp(dir / "out2" / "work_precision.csv"));
    for (const auto& [formulation, methods] : rows)
        for (const auto& [method, list] : methods)
            for (std::size_t i = 0; i < list.size(); ++i) {
                const Row& other = rows2.at(formulation).at(method).at(i);
                BOOST_TEST(other.evals == list[i].evals);
                // ... plus the rounding of each error to double.
                BOOST_TEST(std::abs(other.error - list[i].error) <= tolerance + 0x1p-53 * 2 * list[i].error,
                           formulation << " " << method << ": " << list[i].error << " vs " << other.error);
            }
}

// An orbit that re-enters before t_end has no position there to compare: the reference run
// says so (exit 1, as any integration that cannot go on).
BOOST_AUTO_TEST_CASE(orbit_reference_refuses_a_re_entry) {
    const fs::path dir = scratch("orbit-re-entry");
    const Result r = run(eomc_bench(std::string(EOMC_SOURCE_DIR) + "/scenes/leo_drag.toml", dir / "out",
                                    "--t-end 864000 --formulations cowell --methods dop853 --tolerances 1e-8 "
                                    "--reference-tolerance 1e-14"),
                         dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("the reference run failed: the terminal event 're_entry' occurs between t = ") != std::string::npos,
               r.err);
    BOOST_TEST(!fs::exists(dir / "out" / "work_precision.csv"));
}

BOOST_AUTO_TEST_CASE(orbit_bad_input_exits_2) {
    const fs::path dir = scratch("orbit-bad");
    const fs::path out = dir / "out";
    const fs::path oscillator = write_scene(dir, std::string(oscillator_scene) + oscillator_reference);
    Result r = run(eomc_bench(oscillator, out, "--formulations cowell"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--formulations: error: ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("has no [orbit]") != std::string::npos, r.err);

    r = run(eomc_bench(leo_j2, out, "--formulations cowell,equinoctal"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--formulations: error: unknown orbit formulation 'equinoctal'; did you mean 'equinoctial'?") !=
                   std::string::npos,
               r.err);
    r = run(eomc_bench(leo_j2, out, "--formulations cowell,cowell"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("the formulation 'cowell' is listed twice") != std::string::npos, r.err);
    // A formulation that does not take the scene (mean averages R; drag has no R) is bad input when
    // asked for by name (among all built ones it would be left out with a note).
    r = run(eomc_bench(std::string(EOMC_SOURCE_DIR) + "/scenes/leo_drag.toml", out, "--formulations cowell,mean"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--formulations mean: error: ") != std::string::npos, r.err);
    r = run(eomc_bench(leo_j2, out, "--formulations cowell --orbit-formulation equinoctial"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("either by --formulations or by --orbit-formulation") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(out));
}

// ---------------------------------------------------------------------------------------------
// Rigid-body scenes: the formulation axis. Kovalevskaya's top (scenes/kovalevskaya_top.toml) over
// t = 0 .. 5 in its four formulations, each judged by (ω, γ) at t_end against a float128
// Euler–Poisson run, and by the drift of its energy.
// ---------------------------------------------------------------------------------------------
namespace {

const std::string kovalevskaya = std::string(EOMC_SOURCE_DIR) + "/scenes/kovalevskaya_top.toml";
const std::string rigid_header =
    "formulation,method,library,kind,setting,omega_gamma_error,max_energy_drift,rhs_evals,steps,rejected,"
    "wall_seconds,repetitions";

}  // namespace

BOOST_AUTO_TEST_CASE(rigid_formulations_axis) {
    const fs::path dir = scratch("rigid");
    const Result r = run(eomc_bench(kovalevskaya, dir / "out",
                                    "--t-end 5 --methods rk4,dop853 --tolerances 1e-7,1e-9,1e-11 --steps 200,400,800"),
                         dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto rows = parse_orbit_csv(slurp(dir / "out" / "work_precision.csv"), rigid_header);
    BOOST_TEST(r.out.find("note: reference: kovalevskaya_top_euler_poisson in float128 (113-bit), DOP853 at rtol = atol "
                          "= 1e-26") != std::string::npos,
               r.out);
    BOOST_TEST(r.out.find("away in (p, q, r, gamma1, gamma2, gamma3)") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("times below the smallest error measured") != std::string::npos, r.out);
    // Every formulation, by default (none refuses this scene).
    BOOST_TEST(rows.size() == 4u);
    for (const char* formulation : {"euler_poisson", "quaternion", "euler_angles", "andoyer_deprit"}) {
        BOOST_TEST_CONTEXT(formulation) {
            BOOST_TEST_REQUIRE(rows.count(formulation) == 1u);
            const auto& methods = rows.at(formulation);
            BOOST_TEST(methods.size() == 2u);
            BOOST_TEST(r.out.find(std::string(formulation) + " ") != std::string::npos, "table lacks " << formulation);
            // One row per step count, in sweep order; RK4 calls the kernel 4 times a step.
            BOOST_TEST_REQUIRE(methods.count("rk4") == 1u);
            const auto& rk4 = methods.at("rk4");
            BOOST_TEST_REQUIRE(rk4.size() == 3u);
            for (std::size_t i = 0; i < rk4.size(); ++i) {
                BOOST_TEST(rk4[i].kind == "steps");
                BOOST_TEST(rk4[i].setting == 200.0 * std::pow(2.0, static_cast<double>(i)));
                BOOST_TEST(rk4[i].steps == static_cast<long>(rk4[i].setting));
                BOOST_TEST(rk4[i].evals == 4 * rk4[i].steps);
                // The energy is in every rigid kernel; its drift is measured (and only its).
                BOOST_TEST((std::isfinite(rk4[i].drift) && rk4[i].drift >= 0.0));
            }
            // Order 4 per halving of the step. The global error is C h^4 (1 + O(h/τ)), τ the
            // fastest time scale of the motion (|ω| <= 1.75 here, and the formulations' variables
            // turn at most a few times faster): at h = 5/200 = 0.025 the next term shifts each
            // ratio e(h)/e(h/2) from 16 by O(h/τ) ~ 10%, so the observed order
            // log2(e(h)/e(h/2)) lies within 0.3 of 4, as for the Kepler orbit above (measured
            // 3.84 .. 4.07).
            for (std::size_t i = 1; i < rk4.size(); ++i) {
                const double order = std::log2(rk4[i - 1].error / rk4[i].error);
                BOOST_TEST(std::abs(order - 4.0) <= 0.3,
                           "rk4 " << rk4[i - 1].setting << " -> " << rk4[i].setting << " steps: observed order " << order);
            }
            // An adaptive run: one row per tolerance, errors falling as it tightens.
            BOOST_TEST_REQUIRE(methods.count("dop853") == 1u);
            BOOST_TEST_REQUIRE(methods.at("dop853").size() == 3u);
            check_errors_fall("dop853", methods.at("dop853"));
        }
    }
}

// A formulation that cannot describe the scene's initial state (a top spinning upright: Euler
// angles at gimbal lock, θ = 0; Andoyer–Deprit at L = G) is left out, with the reason, when every
// formulation is swept, and is bad input when asked for by name.
BOOST_AUTO_TEST_CASE(rigid_formulations_left_out_or_refused) {
    const fs::path dir = scratch("rigid-refused");
    const fs::path scene = write_scene(dir, R"toml([scene]
name = "upright_top"
summary = "a symmetric top spinning upright"

[parameters]
P = 1.0

[rigid_body]
inertia = ["1", "1", "0.5"]
center = ["0", "0", "1"]
weight = "P"

[rigid_body.initial]
omega = [0.0, 0.0, 5.0]
vertical = [0.0, 0.0, 1.0]

[simulate]
t_end = 1.0
)toml");
    Result r = run(eomc_bench(scene, dir / "bad", "--formulations euler_poisson,euler_angles"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("scene.toml:15:12: error: the euler_angles formulation cannot start at θ = 0 (sin θ = 0: "
                          "gimbal lock") != std::string::npos,
               r.err);
    r = run(eomc_bench(scene, dir / "bad", "--formulations euler_poisson,quaternoin"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("unknown rigid-body formulation 'quaternoin'; did you mean 'quaternion'?") != std::string::npos,
               r.err);
    r = run(eomc_bench(scene, dir / "bad", "--formulations quaternion --rigid-formulation quaternion"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("either by --formulations or by --rigid-formulation") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "bad"));

    r = run(eomc_bench(scene, dir / "out", "--methods dop853 --tolerances 1e-8"), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("note: euler_angles: left out: ") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("note: andoyer_deprit: left out: ") != std::string::npos, r.out);
    const auto rows = parse_orbit_csv(slurp(dir / "out" / "work_precision.csv"), rigid_header);
    BOOST_TEST(rows.size() == 2u);
    BOOST_TEST(rows.count("euler_poisson") == 1u);
    BOOST_TEST(rows.count("quaternion") == 1u);
}

// A free body has a closed form (Euler–Poinsot): the float128 reference is checked against it, and
// the two agree to the closed form's own double rounding (a few ulps of |ω| ~ 1 after ~10 turns of
// elliptic-function evaluation: 1e-13 leaves room), far below any error the bench measures.
BOOST_AUTO_TEST_CASE(free_body_reference_checked_against_the_closed_form) {
    const fs::path dir = scratch("free_body");
    const Result r = run(eomc_bench(std::string(EOMC_SOURCE_DIR) + "/scenes/euler_poinsot.toml", dir / "out",
                                    "--t-end 20 --methods dop853 --tolerances 1e-8 --formulations euler_poisson"),
                         dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string marker = "note: the reference agrees with the exact Euler-Poinsot motion";
    const std::size_t at = r.out.find(marker);
    BOOST_TEST_REQUIRE(at != std::string::npos, r.out);
    const std::size_t to = r.out.find(" to ", at + marker.size());
    BOOST_TEST_REQUIRE(to != std::string::npos);
    const double distance = std::stod(r.out.substr(to + 4));
    BOOST_TEST(distance < 1e-13, r.out);
    // A heavy top has no closed form to check against.
    BOOST_TEST(run(eomc_bench(kovalevskaya, dir / "heavy", "--t-end 1 --methods dop853 --tolerances 1e-6 "
                                                           "--formulations euler_poisson"),
                   dir)
                   .out.find("Euler-Poinsot") == std::string::npos);
}
