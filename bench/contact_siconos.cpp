// The contact bench (issue 16, Mei ch. 6): eomc against Siconos 4.4 on the bouncing ball and
// Housner's rocking block, event-driven and Moreau–Jean, and a penalty (spring–damper) floor.
//
//   eomc   event-driven: contact/event_driven.hpp with dopri5 over a ladder of tolerances;
//          Moreau–Jean: contact/moreau_jean.hpp (θ = 1/2, γ = 1/2) over a ladder of steps;
//          the kernels are generated/bouncing_ball.hpp and generated/rocking_block.hpp.
//   Siconos EventDriven + LsodarOSI (impact and acceleration LCPs) over the same tolerances;
//          TimeStepping + MoreauJeanOSI(θ = 1/2) + LCP over the same steps.
//   penalty: the ball on a linear spring–damper floor, k over a ladder, c from the target e by the
//          damped oscillator's e = exp(−ζπ/√(1 − ζ²)); dopri5 with the floor's edge located.
//
// Each run goes from t = 0 to 5 (past both Zeno points). Reported: the error of the first three
// impact times and of the tenth against the closed form (the ball) or the mpmath reference (the block,
// bench/contact_reference.py), the error of (q, q̇) at t = 1 and t = 5, the impacts resolved before
// t∞, what the run does at t∞, and the wall time (median of --repeats, the two tools' runs alternated). An impact of a time-stepping
// run is a step with P > 0 after one with P = 0, timed at the step's end (both tools alike).
//
//   cmake --build build --target bench_contact_siconos
//   build/bench/bench_contact_siconos [--repeats N] [--out DIR]   (DIR/contact_{tools,penalty}.{csv,md})
#include <algorithm>
#include <chrono>
#include <utility>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <eomc/runtime/contact/event_driven.hpp>
#include <eomc/runtime/contact/moreau_jean.hpp>
#include <eomc/runtime/integrate.hpp>
#include <eomc/runtime/stepper/dopri5.hpp>

#include "bouncing_ball.hpp"
#include "contact_siconos_peer.hpp"
#include "rocking_block.hpp"

namespace rt = eomc::runtime;
using contact_bench::Run;
using contact_bench::siconos_event_driven;
using contact_bench::siconos_moreau_jean;

namespace {

// --- The two systems and their references -------------------------------------------------------

struct Reference {
    std::string name;
    std::vector<double> impacts;  // t_k
    double t_inf;                 // the Zeno point
    double q1, v1;                // the state at t = 1
    double q5, v5;                // at t = 5 (at rest)
};

// The ball (m = 1, g = 9.81, h0 = 2, e = 0.7): t_1 = √(2 h0/g), t_{k+1} = t_k + 2 e^k v_1/g,
// t∞ = t_1 (1 + e)/(1 − e) (Mei ch. 6); at t = 1 in the flight after the first impact.
Reference ball_reference() {
    const double g = 9.81, e = 0.7, h0 = 2, v1 = std::sqrt(2 * g * h0);
    Reference r{"bouncing_ball", {}, 0, 0, 0, 0, 0};
    double t = v1 / g;
    for (int k = 1; k <= 30; ++k) {
        r.impacts.push_back(t);
        t += 2 * std::pow(e, k) * v1 / g;
    }
    r.t_inf = r.impacts[0] * (1 + e) / (1 - e);
    const double s = 1.0 - r.impacts[0];
    r.q1 = e * v1 * s - g * s * s / 2;
    r.v1 = e * v1 - g * s;
    return r;
}

// The block (b = 0.2, h = 0.6, θ0 = α/2 at rest): bench/contact_reference.py (mpmath, 90 digits).
Reference block_reference() {
    return {"rocking_block",
            {0.38729507631479312, 0.94306967883223288, 1.3771006308584158, 1.7278421754840572, 2.0164340250603142,
             2.2564500131553418, 2.457433538350902, 2.6264953187384797, 2.7691439795059483, 2.8897632122638531,
             2.9919078027759249, 3.0784990467659629, 3.1519605520883421, 3.2143167399973753, 3.2672668625280537},
            3.5667622617538924,
            0.033134346707879298,
            0.48456338285007438,
            0.0,
            0.0};
}

// --- One run's record -----------------------------------------------------------------------------



struct Row {
    std::string system, tool, method;
    double setting;
    double wall = NAN;
    Run run;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// One run of `body` into `row`, its wall time appended to `walls`.
template <class F>
void time_once(Row& row, std::vector<double>& walls, F&& body) {
    Run run;
    const auto start = std::chrono::steady_clock::now();
    try {
        body(run);
    } catch (const std::exception& e) {
        run.failure = e.what();
    } catch (...) {
        run.failure = "unknown exception";
    }
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    row.run = run;
}

template <class F>
Row timed(const std::string& system, const std::string& tool, const std::string& method, double setting, int repeats,
          F&& body) {
    Row row{system, tool, method, setting, NAN, {}};
    std::vector<double> walls;
    for (int i = 0; i < repeats && (i == 0 || row.run.failure.empty()); ++i) time_once(row, walls, body);
    row.wall = median(walls);
    return row;
}

// eomc and Siconos on the same problem, run alternately (eomc, Siconos, eomc, …) so that a shared
// machine's load weighs on both sides alike; each side's wall is the median of its runs. A side that
// failed is not run again.
template <class F, class G>
std::pair<Row, Row> timed_pair(const std::string& system, const std::string& method, double setting, int repeats,
                               F&& eomc_body, G&& siconos_body) {
    Row a{system, "eomc", method, setting, NAN, {}}, b{system, "siconos", method, setting, NAN, {}};
    std::vector<double> wa, wb;
    for (int i = 0; i < repeats; ++i) {
        if (i == 0 || a.run.failure.empty()) time_once(a, wa, eomc_body);
        if (i == 0 || b.run.failure.empty()) time_once(b, wb, siconos_body);
    }
    a.wall = median(wa);
    b.wall = median(wb);
    return {a, b};
}

// --- eomc -----------------------------------------------------------------------------------------

template <class K>
rt::contact::ContactSystem<double> contact_system(const typename K::Parameters& p) {
    using V = rt::contact::Vector<double>;
    using M = rt::contact::Matrix<double>;
    constexpr int n = K::n_coordinates;
    rt::contact::ContactSystem<double> sys;
    sys.dof = n;
    double e[K::n_contacts];
    K::restitutions(p, e);
    for (int a = 0; a < K::n_contacts; ++a) sys.contacts.push_back({e[a], rt::contact::GapLevel::position});
    const auto state = [](const V& q, const V& u) {
        std::array<double, K::n_state> x{};
        for (int k = 0; k < n; ++k) x[std::size_t(k)] = q[k], x[std::size_t(n + k)] = u[k];
        return x;
    };
    sys.mass = [=](double t, const V& q, M& out) {
        const auto x = state(q, V::Zero(n));
        K::mass_matrix(t, x.data(), out.data(), p);  // n = 1: layout does not matter
    };
    sys.force = [=](double t, const V& q, const V& u, V& f) { K::forcing(t, state(q, u).data(), f.data(), p); };
    sys.gaps = [=](double t, const V& q, const V& u, V& g) { K::gaps(t, state(q, u).data(), g.data(), p); };
    sys.rows = [=](double t, const V& q, const V& u, M& W, V& b) {
        const auto x = state(q, u);
        K::contact_jacobian(t, x.data(), W.data(), p);
        K::contact_bias(t, x.data(), b.data(), p);
    };
    return sys;
}
static_assert(eomc::models::BouncingBall::n_coordinates == 1 && eomc::models::RockingBlock::n_coordinates == 1,
              "contact_system copies M and W as flat arrays: one coordinate");

template <class K>
void eomc_event_driven(double rtol, Run& run) {
    const typename K::Parameters p{};
    const auto sys = contact_system<K>(p);
    rt::State<double> x(K::initial_state.begin(), K::initial_state.end());
    rt::contact::EventDrivenOptions<double> options;
    options.zeno_ratios = 8;  // as tests/host/contacts.cpp: the tenth impact is located before the extrapolation
    bool zeno = false;
    double zeno_t = NAN;
    options.on_event = [&](const rt::contact::ContactEvent<double>& e) {
        if (e.kind == rt::contact::ContactEventKind::impact) run.impacts.push_back(e.t);
        if (e.kind == rt::contact::ContactEventKind::zeno) zeno = true, zeno_t = e.t;
    };
    double lambda = NAN;
    const auto observer = [&](double, const rt::State<double>&, const rt::contact::Vector<double>& l,
                              const std::vector<bool>&) { lambda = l[0]; };
    const rt::Tolerances tol{rtol, rtol * 1e-2};
    rt::Dopri5<double> stepper;
    auto a = rt::contact::integrate_event_driven(stepper, sys, x, 0.0, 1.0, tol, observer, options);
    run.q1 = x[0], run.v1 = x[1];
    stepper.reset();
    auto b = rt::contact::integrate_event_driven(stepper, sys, x, 1.0, 5.0, tol, observer, options);
    run.q5 = x[0], run.v5 = x[1], run.lambda5 = lambda;
    run.last_step_count = double(a.stats.accepted + b.stats.accepted);
    char buf[160];
    if (zeno) std::snprintf(buf, sizeof buf, "zeno at %.15g, then contact", zeno_t);
    else std::snprintf(buf, sizeof buf, "no zeno event; active at end %d", int(b.active[0]));
    run.zeno = buf;
}

template <class K>
void eomc_moreau_jean(double h, Run& run) {
    using V = rt::LcpVector<double>;
    using M = rt::LcpMatrix<double>;
    const typename K::Parameters p{};
    const auto x_of = [](const V& q, const V& u) {
        std::array<double, K::n_state> x{};
        x[0] = q[0], x[1] = u[0];
        return x;
    };
    const auto mass = [&](double t, const V& q) {
        M out(1, 1);
        K::mass_matrix(t, x_of(q, V::Zero(1)).data(), out.data(), p);
        return out;
    };
    const auto force = [&](double t, const V& q, const V& u) {
        V f(1);
        K::forcing(t, x_of(q, u).data(), f.data(), p);
        return f;
    };
    const auto gaps = [&](double t, const V& q) {
        V g(1);
        K::gaps(t, x_of(q, V::Zero(1)).data(), g.data(), p);
        return g;
    };
    const auto jacobian = [&](double t, const V& q) {
        M W(1, 1);
        K::contact_jacobian(t, x_of(q, V::Zero(1)).data(), W.data(), p);
        return W;
    };
    V e(1);
    K::restitutions(p, e.data());
    V q(1), u(1);
    q[0] = K::initial_state[0], u[0] = K::initial_state[1];
    double last_p = 0, h_used = h, p_end = 0;
    const auto observer = [&](double t, const V&, const V&, const rt::MoreauJeanStep<double>& s) {
        if (s.P[0] > 0 && !(last_p > 0)) run.impacts.push_back(t);
        last_p = s.P[0];
        p_end = s.P[0];
    };
    long steps = rt::integrate_moreau_jean<double>(mass, force, gaps, jacobian, e, 0.0, 1.0, h, q, u, observer);
    run.q1 = q[0], run.v1 = u[0];
    steps += rt::integrate_moreau_jean<double>(mass, force, gaps, jacobian, e, 1.0, 5.0, h, q, u, observer);
    h_used = 4.0 / std::ceil(4.0 / h - 1e-9);
    run.q5 = q[0], run.v5 = u[0], run.lambda5 = p_end / h_used;
    run.last_step_count = double(steps);
    run.zeno = "passes (time stepping)";
}

// --- Penalty --------------------------------------------------------------------------------------

struct PenaltyRun {
    double k, zeta, c;
    double e_apparent = NAN, duration = NAN, t_second = NAN;  // first impact-and-rebound, next impact
    double y5 = NAN;
    std::size_t contacts_before_tinf = 0, rhs_evals = 0;
    double wall = NAN;
};

// m ÿ = −m g + F, F = −k y − c ẏ while the ball is in the floor (y < 0). The edge y = 0 is located
// on the dense output both ways and the integration restarts there, so that no step straddles the
// jump of the damping force. e = exp(−ζπ/√(1 − ζ²)) gives ζ = −ln e/√(π² + ln² e).
PenaltyRun penalty(double k, double rtol, int repeats) {
    const double m = 1, g = 9.81, e = 0.7, h0 = 2;
    PenaltyRun out{k, 0, 0};
    const double L = std::log(e);
    out.zeta = -L / std::sqrt(std::numbers::pi * std::numbers::pi + L * L);
    out.c = 2 * out.zeta * std::sqrt(k * m);
    const double t_inf = ball_reference().t_inf;
    std::vector<double> walls;
    for (int r = 0; r < repeats; ++r) {
        const auto sys = [&](double, const rt::State<double>& x, rt::State<double>& d) {
            d[0] = x[1];
            d[1] = -g + (x[0] < 0 ? (-k * x[0] - out.c * x[1]) / m : 0.0);
        };
        rt::State<double> x{h0, 0.0};
        // The restart at the edge needs a cooldown: the located state lies on y = 0 to round-off,
        // and without one the same crossing fires again at once (1e-12 s is far below the shortest
        // contact, π/ω ≥ 3e-4 s at k = 1e8, and any flight the run resolves).
        std::vector<rt::EventSpec> specs{{rt::EventDirection::both, false, rt::EventAction::edit, 1e-12}};
        rt::EventLocator<double> locator(specs);
        const auto gap = [](double, const rt::State<double>& xs, rt::State<double>& o) { o[0] = xs[0]; };
        std::vector<double> downs, ups, v_down, v_up;
        const auto edit = [&](const rt::EventHit<double>& hit, rt::State<double>&) {
            (hit.direction < 0 ? downs : ups).push_back(hit.t);
            (hit.direction < 0 ? v_down : v_up).push_back(hit.x[1]);
        };
        rt::Dopri5<double> stepper;
        const auto start = std::chrono::steady_clock::now();
        const auto res = rt::integrate_adaptive_events(stepper, sys, x, 0.0, 5.0, 0.0, rt::Tolerances{rtol, rtol * 1e-2},
                                                       locator, gap, [](double, const rt::State<double>&) {},
                                                       [](const rt::EventHit<double>&) {}, edit);
        walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        out.rhs_evals = res.stats.rhs_evals;
        if (!ups.empty()) {
            out.e_apparent = -v_up[0] / v_down[0];
            out.duration = ups[0] - downs[0];
        }
        if (downs.size() > 1) out.t_second = downs[1];
        out.contacts_before_tinf = std::size_t(std::count_if(downs.begin(), downs.end(), [&](double t) { return t < t_inf; }));
        out.y5 = x[0];
    }
    out.wall = median(walls);
    return out;
}

// --- Output ---------------------------------------------------------------------------------------

double max_error(const std::vector<double>& got, const std::vector<double>& ref, std::size_t from, std::size_t to) {
    double err = 0;
    for (std::size_t i = from; i < to; ++i) {
        if (i >= got.size()) return NAN;
        err = std::max(err, std::abs(got[i] - ref[i]));
    }
    return err;
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 5;
    std::string out_dir = ".";
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out_dir = argv[++i];
        else {
            std::fprintf(stderr, "usage: %s [--repeats N] [--out DIR]\n", argv[0]);
            return 2;
        }
    }
    const std::vector<double> tolerances{1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
    const std::vector<double> steps{1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5};  // 1/h whole: t = 1 on the grid
    std::vector<Row> rows;
    for (const bool is_block : {false, true}) {
        const Reference ref = is_block ? block_reference() : ball_reference();
        const auto add = [&](std::pair<Row, Row> pair) {
            rows.push_back(std::move(pair.first));
            rows.push_back(std::move(pair.second));
        };
        for (double tol : tolerances) {
            add(timed_pair(
                ref.name, "event_driven", tol, repeats,
                [&](Run& r) {
                    if (is_block) eomc_event_driven<eomc::models::RockingBlock>(tol, r);
                    else eomc_event_driven<eomc::models::BouncingBall>(tol, r);
                },
                [&](Run& r) { siconos_event_driven(is_block, tol, r); }));
        }
        for (double h : steps) {
            const int rep = h < 1e-4 ? std::max(1, repeats / 2) : repeats;
            add(timed_pair(
                ref.name, "moreau_jean", h, rep,
                [&](Run& r) {
                    if (is_block) eomc_moreau_jean<eomc::models::RockingBlock>(h, r);
                    else eomc_moreau_jean<eomc::models::BouncingBall>(h, r);
                },
                [&](Run& r) { siconos_moreau_jean(is_block, h, r); }));
        }
    }

    const std::string csv_path = out_dir + "/contact_tools.csv";
    std::FILE* csv = std::fopen(csv_path.c_str(), "w");
    if (!csv) {
        std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
        return 1;
    }
    const std::string md_path = out_dir + "/contact_tools.md";
    std::FILE* md = std::fopen(md_path.c_str(), "w");
    if (!md) {
        std::fprintf(stderr, "cannot write %s\n", md_path.c_str());
        return 1;
    }
    std::fprintf(csv, "system,tool,method,setting,wall_s,steps_or_events,err_t1_3,err_t10,err_state_t1,err_state_t5,"
                      "impacts_before_tinf,last_impact,lambda_end,zeno,failure\n");
    std::fprintf(md, "| system | tool | method | rtol or h | wall (s) | steps/events | err t1..t3 | err t10 | err (q,v)(1) | "
                "err (q,v)(5) | impacts < t∞ | λ at 5 | at the Zeno point |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for (const Row& row : rows) {
        const Reference ref = row.system == "rocking_block" ? block_reference() : ball_reference();
        const Run& r = row.run;
        const double e3 = max_error(r.impacts, ref.impacts, 0, 3), e10 = max_error(r.impacts, ref.impacts, 9, 10);
        const double s1 = std::max(std::abs(r.q1 - ref.q1), std::abs(r.v1 - ref.v1));
        const double s5 = std::max(std::abs(r.q5 - ref.q5), std::abs(r.v5 - ref.v5));
        std::size_t before = 0;
        double last = NAN;
        for (double t : r.impacts)
            if (t < ref.t_inf) ++before, last = t;
        std::fprintf(csv, "%s,%s,%s,%g,%.6g,%.0f,%.3e,%.3e,%.3e,%.3e,%zu,%.15g,%.10g,\"%s\",\"%s\"\n", row.system.c_str(),
                     row.tool.c_str(), row.method.c_str(), row.setting, row.wall, r.last_step_count, e3, e10, s1, s5,
                     before, last, r.lambda5, r.zeno.c_str(), r.failure.c_str());
        std::fprintf(md, "| %s | %s | %s | %g | %.3g | %.0f | %.1e | %.1e | %.1e | %.1e | %zu | %.6g | %s%s%s |\n",
                    row.system.c_str(), row.tool.c_str(), row.method.c_str(), row.setting, row.wall,
                    r.last_step_count, e3, e10, s1, s5, before, r.lambda5, r.zeno.c_str(),
                    r.failure.empty() ? "" : "; FAILED: ", r.failure.c_str());
    }
    std::fclose(csv);
    std::fclose(md);

    // Penalty against stiffness, beside the event-driven ball at the same tolerance.
    const double rtol = 1e-10;
    const std::string pen_path = out_dir + "/contact_penalty.csv";
    std::FILE* pen = std::fopen(pen_path.c_str(), "w");
    md = std::fopen((out_dir + "/contact_penalty.md").c_str(), "w");
    if (!pen || !md) {
        std::fprintf(stderr, "cannot write %s\n", pen_path.c_str());
        return 1;
    }
    const Reference ball = ball_reference();
    std::fprintf(pen, "model,k,zeta,c,wall_s,rhs_evals,e_apparent_error,contact_duration,t2_error,contacts_before_tinf,y_at_5\n");
    std::fprintf(md, "| model | k (N/m) | c (N s/m) | wall (s) | rhs evals | e_apparent − e | contact duration (s) | t2 error | "
                "contacts < t∞ | y(5) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (double k : {1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8}) {
        const PenaltyRun p = penalty(k, rtol, repeats);
        std::fprintf(pen, "penalty,%g,%.6f,%.6g,%.6g,%zu,%.3e,%.3e,%.3e,%zu,%.3e\n", k, p.zeta, p.c, p.wall, p.rhs_evals,
                     p.e_apparent - 0.7, p.duration, p.t_second - ball.impacts[1], p.contacts_before_tinf, p.y5);
        std::fprintf(md, "| penalty | %g | %.4g | %.3g | %zu | %.2e | %.2e | %.2e | %zu | %.2e |\n", k, p.c, p.wall, p.rhs_evals,
                    p.e_apparent - 0.7, p.duration, p.t_second - ball.impacts[1], p.contacts_before_tinf, p.y5);
    }
    // The event-driven ball at the same tolerance: e exact by construction (Newton's law), no duration.
    {
        const Row ed = timed("bouncing_ball", "eomc", "event_driven", rtol, repeats,
                             [&](Run& r) { eomc_event_driven<eomc::models::BouncingBall>(rtol, r); });
        std::size_t before = 0;
        for (double t : ed.run.impacts) before += t < ball.t_inf;
        const double t2 = ed.run.impacts.size() > 1 ? ed.run.impacts[1] - ball.impacts[1] : NAN;
        std::fprintf(pen, "event_driven,inf,,,%.6g,,0,0,%.3e,%zu,%.3e\n", ed.wall, t2, before, ed.run.q5);
        std::fprintf(md, "| eomc event_driven | ∞ | – | %.3g | – | 0 (Newton's law) | 0 | %.2e | %zu | %.2e |\n", ed.wall, t2,
                    before, ed.run.q5);
    }
    std::fclose(pen);
    std::fclose(md);
    return 0;
}
