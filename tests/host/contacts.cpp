// Unilateral rows end to end (issue 16, the kernel and host side): scenes without [[unilateral]]
// tables get gap rows appended by hand to their first-order form (as tests/host/constraints.cpp
// does for bilateral rows), are lowered, emitted, compiled and run through eomc simulate with the
// event-driven driver and with Moreau–Jean time stepping. Known answers (mpmath): Mei, Special
// Topics in Analytical Mechanics, ch. 6 (Newton's law, Carnot's theorem, the bouncing ball's Zeno
// point); Acary, Brogliato, Numerical Methods for Nonsmooth Dynamical Systems, Springer 2008.
#define BOOST_TEST_MODULE simulate_contacts
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "host/toolchain.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "support/diagnostic.hpp"

#include "csv.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double m = 1.5, g = 9.81, h0 = 2.0, e_ball = 0.7;

const char* const ball = R"toml([scene]
name = "bouncing_ball"
[parameters]
m = 1.5
g = 9.81
e = 0.7
[coordinates]
y = { initial = 2.0, rate = 0.0 }
[lagrangian]
T = "m*y_dot^2/2"
V = "m*g*y"
)toml";

// θ from the vertical, the wall at θ = 0, released at 90°.
const char* const pendulum = R"toml([scene]
name = "pendulum_wall"
[parameters]
m = 1.0
g = 9.81
l = 0.5
e = 0.6
[coordinates]
theta = { initial = 1.5707963267948966, rate = 0.0 }
[lagrangian]
T = "m*l^2*theta_dot^2/2"
V = "-m*g*l*cos(theta)"
)toml";

const GiNaC::symbol& parameter(const eomc::model::Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    throw std::runtime_error("no parameter " + name);
}

// The scene's kernel with the gap f = q_0 ≥ 0 (W = [1], bias 0) and restitution e appended.
// quasi: the coordinate's rate made 2 u instead of u (a kernel whose velocity is not q̇).
test_support::Kernel gap_kernel(const char* scene, const std::string& row_name, bool quasi = false) {
    const auto model = test_support::model_of(scene);
    auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    BOOST_REQUIRE(form.state.size() == 2u);
    const GiNaC::ex q = form.state[0].symbol, u = form.state[1].symbol;
    eomc::mechanics::UnilateralRow row;
    row.row.name = row_name;
    row.row.holonomic = true;
    row.row.position = q;
    row.row.velocity = u;
    row.row.W = {GiNaC::ex(1)};
    row.row.bias = 0;
    row.row.lambda = GiNaC::symbol("lambda_" + row_name);
    row.restitution = parameter(model, "e");
    form.unilateral.push_back(row);
    if (quasi)
        for (auto& [index, rate] : form.explicit_rates)
            if (index == 0) rate = 2 * u;
    const auto ir = eomc::codegen::lower(model, form);
    return {eomc::codegen::emit_header(ir, {EOMC_VERSION, false}), model.struct_name};
}

eomc::host::SimulationRequest request(const test_support::Kernel& k, double t_end, double rtol = 1e-12) {
    auto r = test_support::simulation_request(k, t_end);
    r.rtol = rtol;
    r.atol = rtol * 1e-2;
    return r;
}

// The bouncing ball's impact times from h0 (mpmath): t_1 = √(2 h0/g), t_{k+1} = t_k + 2 e^k v_1/g.
double impact_time(int k) {
    const double v1 = std::sqrt(2 * g * h0);
    double t = v1 / g;
    for (int i = 1; i < k; ++i) t += 2 * std::pow(e_ball, i) * v1 / g;
    return t;
}
constexpr double zeno_time = 3.61845485527991;

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string c; std::getline(in, c, ',');) out.push_back(c);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

// A strict little JSON checker (RFC 8259's grammar; no value semantics): true when `s` is one value.
class JsonChecker {
public:
    explicit JsonChecker(const std::string& s) : s_(s) {}
    bool valid() {
        ws();
        if (!value()) return false;
        ws();
        return i_ == s_.size();
    }

private:
    void ws() {
        while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
    }
    bool lit(const char* w) {
        const std::string word(w);
        if (s_.compare(i_, word.size(), word) != 0) return false;
        i_ += word.size();
        return true;
    }
    bool string() {
        if (i_ >= s_.size() || s_[i_] != '"') return false;
        for (++i_; i_ < s_.size(); ++i_) {
            if (s_[i_] == '\\') ++i_;
            else if (s_[i_] == '"') return ++i_, true;
        }
        return false;
    }
    bool number() {
        const std::size_t start = i_;
        while (i_ < s_.size() && std::string("+-0123456789.eE").find(s_[i_]) != std::string::npos) ++i_;
        if (i_ == start) return false;
        try {
            std::size_t used = 0;
            (void)std::stod(s_.substr(start, i_ - start), &used);
            return used == i_ - start;
        } catch (...) {
            return false;
        }
    }
    template <class Item>
    bool sequence(char close, Item item) {
        ++i_;
        ws();
        if (i_ < s_.size() && s_[i_] == close) return ++i_, true;
        for (;;) {
            ws();
            if (!item()) return false;
            ws();
            if (i_ >= s_.size()) return false;
            if (s_[i_] == close) return ++i_, true;
            if (s_[i_] != ',') return false;
            ++i_;
        }
    }
    bool value() {
        if (i_ >= s_.size()) return false;
        switch (s_[i_]) {
            case '{':
                return sequence('}', [&] {
                    if (!string()) return false;
                    ws();
                    if (i_ >= s_.size() || s_[i_] != ':') return false;
                    ++i_;
                    ws();
                    return value();
                });
            case '[': return sequence(']', [&] { return value(); });
            case '"': return string();
            case 't': return lit("true");
            case 'f': return lit("false");
            case 'n': return lit("null");
            default: return number();
        }
    }
    const std::string& s_;
    std::size_t i_ = 0;
};

}  // namespace

// The kernel's contact part compiles warning-free for double and long double and satisfies
// runtime::ContactKernel; a kernel without rows keeps no trace of it.
BOOST_AUTO_TEST_CASE(contact_kernel_compiles_cleanly) {
    const auto k = gap_kernel(ball, "floor");
    BOOST_TEST(k.header.find("n_contacts = 1") != std::string::npos);
    BOOST_TEST(k.header.find("contact_names{ \"floor\" }") != std::string::npos);
    BOOST_TEST(k.header.find("contact_kinematic{ false }") != std::string::npos);
    BOOST_TEST(test_support::kernel_of(ball).header.find("n_contacts") == std::string::npos);
    eomc::host::CompileRequest c;
    const std::string check = R"(#include "kernel.hpp"
#include <eomc/runtime/kernel.hpp>
namespace rt = eomc::runtime;
using K = eomc::models::)" + k.struct_name + R"(;
static_assert(rt::GeneratedKernel<K> && rt::GeneratedKernel<K, long double>);
static_assert(rt::ContactKernel<K> && rt::ContactKernel<K, long double>);
template <class S>
S exercise() {
    const K::Parameters p{};
    S x[K::n_state], e[K::n_contacts], g[K::n_contacts], W[K::n_contacts * K::n_velocities], b[K::n_contacts];
    for (int i = 0; i < K::n_state; ++i) x[i] = S(K::initial_state[std::size_t(i)]);
    K::restitutions(p, e);
    K::gaps(S(0), x, g, p);
    K::contact_jacobian(S(0), x, W, p);
    K::contact_bias(S(0), x, b, p);
    return e[0] + g[0] + W[0] + b[0];
}
double check() { return exercise<double>() + double(exercise<long double>()); }
)";
    c.files = {{"check.cpp", check}, {"kernel.hpp", k.header}};
    c.flags = {"-c", "-Wall", "-Wextra", "-Werror", "-pedantic"};
    c.suffix = ".o";
    c.what = "the contact kernel's compile check";
    BOOST_CHECK_NO_THROW(eomc::host::find_or_compile(c, test_support::test_cache_dir));
}

// The ball dropped from h0 = 2 with e = 0.7 (event-driven, dopri5, rtol 1e-12, atol 1e-14). Free
// flight under constant gravity is a quadratic, which dopri5 integrates exactly, so every impact
// time is the located root of the dense output to round-off: errors of a few ulp of t per impact,
// accumulated over ten, bounded by 1e-11. The Zeno point is the geometric series' sum, extrapolated
// to within its own error bound (the driver waits until it is below rtol |t| + atol): 1e-10.
// After it, rest on the floor with λ = m g to round-off (1e-12 relative). Each impact has
// ḟ⁺ = −e ḟ⁻ and T⁺ = e² T⁻, i.e. ΔT = (e² − 1) m ḟ⁻²/2, which is also Carnot's
// −((1 − e)/(1 + e)) m Δu²/2 (relative 1e-12).
// The driver extrapolates once zeno_ratios interval ratios agree and the intervals are no longer
// resolved (below 100 impact-time errors): ten impacts and more happen first.
BOOST_AUTO_TEST_CASE(bouncing_ball_event_driven) {
    auto r = request(gap_kernel(ball, "floor"), 4.5);
    r.zeno_ratios = 8;
    const fs::path csv = fs::path(EOMC_BINARY_DIR) / "test-output" / "contacts_ball.csv";
    fs::create_directories(csv.parent_path());
    r.csv_path = csv.string();
    const auto result = eomc::host::simulate(r);

    std::vector<const eomc::host::ContactEventReport*> impacts, zeno;
    for (const auto& e : result.contact_events) {
        if (e.kind == "impact") impacts.push_back(&e);
        if (e.kind == "zeno") zeno.push_back(&e);
    }
    BOOST_REQUIRE(impacts.size() >= 10u);
    const double expected[] = {0.638550856814101, 1.53252205635384, 2.15830189603166};
    for (int k = 0; k < 3; ++k) {
        BOOST_TEST_MESSAGE("impact " << k + 1 << ": t = " << impacts[k]->t << ", error " << impacts[k]->t - expected[k]);
        BOOST_TEST(std::abs(impacts[k]->t - expected[k]) <= 1e-11);
        BOOST_TEST(std::abs(impact_time(k + 1) - expected[k]) <= 1e-13);  // the closed form itself
    }
    BOOST_TEST_MESSAGE("impact 10: t = " << impacts[9]->t << ", error " << impacts[9]->t - 3.49820498042809);
    BOOST_TEST(std::abs(impacts[9]->t - 3.49820498042809) <= 1e-11);
    for (const auto* e : impacts) {
        const double before = e->rate_before, T_minus = m * before * before / 2;
        BOOST_TEST(e->rate_after == -e_ball * before, boost::test_tools::tolerance(1e-12));
        BOOST_TEST(e->impulse == -(1 + e_ball) * m * before, boost::test_tools::tolerance(1e-12));
        BOOST_TEST(T_minus + e->energy_change == e_ball * e_ball * T_minus, boost::test_tools::tolerance(1e-10));
        BOOST_TEST(e->carnot == e->energy_change, boost::test_tools::tolerance(1e-10));
    }
    BOOST_REQUIRE(zeno.size() == 1u);
    BOOST_TEST_MESSAGE("Zeno at " << zeno[0]->t << ", error " << zeno[0]->t - zeno_time << ", after "
                                  << impacts.size() << " impacts, bound " << zeno[0]->extrapolation_error);
    BOOST_TEST(std::abs(zeno[0]->t - zeno_time) <= 1e-10);
    BOOST_TEST(zeno[0]->ratio == e_ball, boost::test_tools::tolerance(1e-6));
    // At rest on the floor, in the contact phase with λ = m g.
    BOOST_TEST(std::abs(result.value("y")) <= 1e-12);
    BOOST_TEST(std::abs(result.value("y_dot")) <= 1e-12);
    BOOST_REQUIRE(result.contacts.size() == 1u);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_floor") == m * g, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(result.t == 4.5);

    // The CSV: λ and the active set after the outputs, then the event column with one labelled
    // row per event.
    const auto lines = test_support::read_lines(csv);
    BOOST_REQUIRE(lines.size() > 20u);
    const auto header = cells(lines[0]);
    BOOST_TEST(lines[0] == "t,y,y_dot,energy,lambda_floor,active,event");
    std::size_t impact_rows = 0, zeno_rows = 0, contact_rows = 0;
    double t_prev = -1;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto row = cells(lines[i]);
        BOOST_REQUIRE(row.size() == header.size());
        const double t = std::stod(row[0]);
        BOOST_TEST(t >= t_prev);
        t_prev = t;
        impact_rows += row.back() == "impact:floor";
        zeno_rows += row.back() == "zeno:floor";
        contact_rows += row.back() == "contact:floor";
        if (row.back() == "contact:floor") {
            BOOST_TEST(row[5] == "1");
            BOOST_TEST(std::stod(row[4]) == m * g, boost::test_tools::tolerance(1e-12));
        }
        // An impact's row holds the state after its whole transition: the last one, where the Zeno
        // point and the contact phase follow at once, is already active.
        if (row.back() == "impact:floor" && t < impacts.back()->t) BOOST_TEST(row[5] == "0");
    }
    BOOST_TEST(impact_rows == impacts.size());
    BOOST_TEST(zeno_rows == 1u);
    BOOST_TEST(contact_rows == 1u);
    const auto last = cells(lines.back());
    BOOST_TEST(last[5] == "1");

    // The summaries: JSON that parses, with every impact; text with the impact table and the Zeno point.
    std::ostringstream json, text;
    eomc::host::print_summary(result, "json", json);
    eomc::host::print_summary(result, "text", text);
    BOOST_TEST_MESSAGE(text.str());
    BOOST_TEST(JsonChecker(json.str()).valid(), json.str());
    BOOST_TEST(json.str().find("\"contacts\": {\"method\": \"event_driven\"") != std::string::npos);
    BOOST_TEST(json.str().find("\"zeno\": [{\"row\": \"floor\", \"t\": 3.618454855") != std::string::npos);
    for (const char* fragment : {"contacts    event_driven", "impacts     ", "Carnot", "zeno        floor at t = 3.618454855",
                                 "contact     floor at t = 3.618454855"})
        BOOST_TEST(text.str().find(fragment) != std::string::npos, "missing '" << fragment << "'");

    // The energy across the impacts. Between them the integrator's drift only: each accepted step
    // may move y and ẏ by its tolerance (rtol |x| + atol), i.e. E by (m g + m |ẏ|max) of that, and
    // the steps add up; dopri5 on a quadratic flight does far better (round-off). At the jumps
    // Carnot's losses, and at the Zeno point what the last bounce still held, T⁺ = ½ m ḟ⁺².
    BOOST_REQUIRE(result.invariants.size() == 1u);
    const auto& E = result.invariants[0];
    const double E0 = m * g * h0, v_max = std::sqrt(2 * g * h0);
    const double per_step = 1e-12 * (h0 + v_max) + 2e-14, drift_bound = double(result.steps) * per_step * m * (g + v_max);
    double carnot_sum = 0;
    for (const auto* e : impacts) carnot_sum += e->carnot;
    const double T_last = 0.5 * m * impacts.back()->rate_after * impacts.back()->rate_after;
    BOOST_TEST_MESSAGE("energy: drift between jumps " << E.max_abs_drift << " (bound " << drift_bound << "), "
                                                      << E.jumps << " jumps changed it by " << E.jump_change);
    BOOST_TEST(E.initial == E0, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(E.jumps == impacts.size() + 1);
    BOOST_TEST(E.max_abs_drift <= drift_bound);
    BOOST_TEST(std::abs(E.final - E.initial - E.jump_change) <= double(E.jumps + 1) * E.max_abs_drift + 1e-14 * E0);
    BOOST_TEST(std::abs(E.jump_change - (carnot_sum - T_last)) <= double(E.jumps) * 1e-12 * E0);
    BOOST_TEST(json.str().find("\"change_at_jumps\"") != std::string::npos);
    BOOST_TEST(json.str().find("\"carnot_balance\": {\"sum_energy_change\"") != std::string::npos);
}

// Issue 28, the energy across impacts with e = 0.8 up to t = 5, before the Zeno point at
// t₁ (1 + e)/(1 − e) ≈ 5.75: nine impacts, each taking Carnot's loss. The summary keeps the two
// apart. (a) Between the impacts the integrator's drift only: an accepted step's error is within
// its tolerance, |δy| ≤ rtol h0 + atol, |δẏ| ≤ rtol v_max + atol (√2 for the error norm's mean over
// two components), and moves E = m ẏ²/2 + m g y by m g |δy| + m v_max |δẏ|; a phase's drift is
// at most the sum over its steps. (Dopri5 integrates this quadratic flight exactly: round-off.)
// (b) At each impact the measured ΔT = m (ḟ⁺² − ḟ⁻²)/2 against Carnot's −m (1 − e)/(1 + e)
// (ḟ⁺ − ḟ⁻)²/2: equal in exact arithmetic, so they differ by the rounding of a few products of
// size ≤ E0, 8 ε E0. The energy's change at the jumps, read from the rows before and after each
// impact, is then Σ Carnot to that rounding per jump, and E(t_end) − E(0) is Σ Carnot within the
// drift of the ten smooth phases.
BOOST_AUTO_TEST_CASE(energy_report_across_impacts) {
    constexpr double eps = std::numeric_limits<double>::epsilon(), e_restitution = 0.8;
    auto r = request(gap_kernel(ball, "floor"), 5.0, 1e-10);
    r.overrides = {{"e", e_restitution}};
    const auto result = eomc::host::simulate(r);
    std::vector<const eomc::host::ContactEventReport*> impacts;
    for (const auto& e : result.contact_events) {
        BOOST_TEST(e.kind != "zeno");
        if (e.kind == "impact") impacts.push_back(&e);
    }
    BOOST_REQUIRE(impacts.size() == 9u);
    BOOST_REQUIRE(result.invariants.size() == 1u);
    const auto& E = result.invariants[0];
    const double E0 = m * g * h0, v_max = std::sqrt(2 * g * h0);
    const double per_step = std::sqrt(2.0) * m * (g * (r.rtol * h0 + r.atol) + v_max * (r.rtol * v_max + r.atol));
    const double drift_bound = double(result.steps) * per_step, rounding = 8 * eps * E0;
    double carnot = 0, worst = 0;
    for (const auto* e : impacts) {
        carnot += e->carnot;
        worst = std::max(worst, std::abs(e->energy_change - e->carnot));
        BOOST_TEST(e->carnot < 0);
    }
    std::ostringstream json;
    eomc::host::print_summary(result, "json", json);
    const std::string key = "\"carnot_balance\": {\"sum_energy_change\": ";
    const auto at = json.str().find(key);
    BOOST_REQUIRE(at != std::string::npos);
    const auto diff_at = json.str().find("\"max_abs_difference\": ", at);
    BOOST_REQUIRE(diff_at != std::string::npos);
    const double reported_worst = std::stod(json.str().substr(diff_at + 22));
    BOOST_TEST_MESSAGE("e = 0.8: drift between the " << E.jumps << " impacts " << E.max_abs_drift << " (bound "
                                                      << drift_bound << "), change at them " << E.jump_change
                                                      << ", sum of Carnot " << carnot << ", largest |dT - Carnot| "
                                                      << worst << " (bound " << rounding << ")");
    BOOST_TEST(E.jumps == impacts.size());
    BOOST_TEST(E.max_abs_drift <= drift_bound);
    BOOST_TEST(worst <= rounding);
    BOOST_TEST(reported_worst == worst);
    BOOST_TEST(std::abs(E.jump_change - carnot) <= double(E.jumps) * 2 * rounding);
    BOOST_TEST(std::abs(E.final - E.initial - carnot) <= double(E.jumps + 1) * E.max_abs_drift + double(E.jumps) * 2 * rounding);
    // The loss is Carnot's, not the drift: each impact keeps e² of the energy, up to m g |y| at the
    // located impact, |y| ≤ v_max times the locator's few ulps of t (8 ε t_end), and the drifts.
    const double located = m * g * v_max * 8 * eps * r.t_end;
    BOOST_TEST(std::abs(E.final - E0 * std::pow(e_restitution, 18)) <=
               double(E.jumps + 1) * E.max_abs_drift + double(E.jumps) * (2 * rounding + located));
}

// With the default Zeno detection (three agreeing ratios) the same limit, to the same bound, and the
// same rest.
BOOST_AUTO_TEST_CASE(bouncing_ball_default_zeno) {
    const auto result = eomc::host::simulate(request(gap_kernel(ball, "floor"), 4.5));
    std::size_t impacts = 0;
    const eomc::host::ContactEventReport* zeno = nullptr;
    for (const auto& e : result.contact_events) {
        impacts += e.kind == "impact";
        if (e.kind == "zeno") zeno = &e;
    }
    BOOST_REQUIRE(zeno);
    BOOST_TEST_MESSAGE("default: Zeno at " << zeno->t << " after " << impacts << " impacts, error " << zeno->t - zeno_time);
    BOOST_TEST(std::abs(zeno->t - zeno_time) <= 1e-10);
    BOOST_TEST(std::abs(result.value("y")) <= 1e-12);
    BOOST_TEST(result.value("lambda_floor") == m * g, boost::test_tools::tolerance(1e-12));
}

// The pendulum l = 0.5 released at 90° towards the wall θ = 0 (e = 0.6): the first impact at
// 0.41857927447728 with |θ̇⁻| = √(2g/l) = 6.26418390534633 (mpmath). The smooth phase is no
// polynomial: with rtol 1e-12 (atol 1e-14) the located time carries the integrator's global error,
// about rtol over a few dozen steps: 1e-9 on t and on θ̇⁻ (relative).
BOOST_AUTO_TEST_CASE(pendulum_against_a_wall) {
    const auto result = eomc::host::simulate(request(gap_kernel(pendulum, "wall"), 1.0));
    const eomc::host::ContactEventReport* first = nullptr;
    for (const auto& e : result.contact_events)
        if (e.kind == "impact" && !first) first = &e;
    BOOST_REQUIRE(first);
    BOOST_TEST_MESSAGE("first impact: t = " << first->t << " (error " << first->t - 0.41857927447728 << "), rate "
                                            << first->rate_before << " (error "
                                            << std::abs(first->rate_before) - 6.26418390534633 << ")");
    BOOST_TEST(std::abs(first->t - 0.41857927447728) <= 1e-9);
    BOOST_TEST(std::abs(first->rate_before) == 6.26418390534633, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(first->rate_after == -0.6 * first->rate_before, boost::test_tools::tolerance(1e-12));
}

// Moreau–Jean (θ = 1/2, h = 1e-3) on the same ball: order one, so the impacts come within O(h) of
// the exact times (the impact is the step whose start is predicted active: at most two steps
// late), the accumulation is passed in finitely many steps, and after the Zeno time the ball rests:
// |ẏ| at round-off, the gap within O(h g h) of zero, the impulse over each step m g h (λ = P/h = m g).
BOOST_AUTO_TEST_CASE(bouncing_ball_moreau_jean) {
    auto r = request(gap_kernel(ball, "floor"), 4.5);
    r.contact_method = "moreau_jean";
    r.step = 1e-3;
    const fs::path csv = fs::path(EOMC_BINARY_DIR) / "test-output" / "contacts_ball_mj.csv";
    fs::create_directories(csv.parent_path());
    r.csv_path = csv.string();
    const auto result = eomc::host::simulate(r);
    std::vector<double> impacts;
    for (const auto& e : result.contact_events)
        if (e.kind == "impact") impacts.push_back(e.t);
    BOOST_REQUIRE(impacts.size() >= 5u);
    for (int k = 0; k < 5; ++k) {
        BOOST_TEST_MESSAGE("impact " << k + 1 << ": t = " << impacts[std::size_t(k)] << ", error "
                                     << impacts[std::size_t(k)] - impact_time(k + 1));
        BOOST_TEST(std::abs(impacts[std::size_t(k)] - impact_time(k + 1)) <= 3 * r.step);
    }
    for (double t : impacts) BOOST_TEST(t <= zeno_time + 3 * r.step);
    BOOST_TEST(result.steps == 4500u);
    BOOST_TEST(std::abs(result.value("y_dot")) <= 1e-12);
    BOOST_TEST(std::abs(result.value("y")) <= g * r.step * r.step);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_floor") == m * g, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(result.contact_method == "moreau_jean");
    // At rest from some step after the Zeno time on: the last row is active, and every row past
    // zeno_time + 0.05 too.
    const auto lines = test_support::read_lines(csv);
    BOOST_TEST(lines[0] == "t,y,y_dot,energy,lambda_floor,active,event");
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto row = cells(lines[i]);
        if (std::stod(row[0]) > zeno_time + 0.05) BOOST_TEST(row[5] == "1");
    }
    std::ostringstream json;
    eomc::host::print_summary(result, "json", json);
    BOOST_TEST(JsonChecker(json.str()).valid(), json.str());
}

// The drivers assume q̇ = u: a kernel whose coordinate rate is another function of the velocity
// (here q̇ = 2u, as quasi-velocities would have it) is refused before anything runs, by name.
BOOST_AUTO_TEST_CASE(quasi_velocities_are_refused) {
    const auto r = request(gap_kernel(ball, "floor", true), 1.0);
    BOOST_CHECK_EXCEPTION(eomc::host::simulate(r), eomc::InputError, [](const eomc::InputError& e) {
        const std::string what = e.what();
        BOOST_TEST_MESSAGE(what);
        return what.find("quasi-velocities") != std::string::npos && what.find("q̇ = u") != std::string::npos;
    });
    // And a bad method name, and an integrator without dense output for the event driver.
    auto bad = request(gap_kernel(ball, "floor"), 1.0);
    bad.contact_method = "penalty";
    BOOST_CHECK_THROW(eomc::host::simulate(bad), eomc::InputError);
    bad.contact_method = "event_driven";
    bad.integrator = "rk4";
    BOOST_CHECK_THROW(eomc::host::simulate(bad), eomc::InputError);
}

// End to end from a scene's [[unilateral]] table: a particle leaving the top of a smooth sphere
// R = 2 at v0 = 1.5 (g = 9.81). It is in contact from t = 0 with λ = m (g − v0²/R) (the gap
// (x² + y² − R²)/(2R) has the unit normal as W, so λ is the normal force) and leaves where
// cos θ = (v0²/(gR) + 2)/3 = 0.704892966360856, at t = 0.717367168216632 (mpmath). The separation
// is located on λ to the integrator's error: at rtol 1e-12 over a time of order 1, 1e-10 bounds
// it in t and in cos θ (measured 1.3e-13, 3e-14).
BOOST_AUTO_TEST_CASE(particle_leaves_a_sphere_from_its_scene) {
    const std::string scene = R"toml([scene]
name = "particle_on_sphere"
[parameters]
m = 1.0
g = 9.81
R = 2.0
[coordinates]
x = { initial = 0.0, rate = 1.5 }
y = { initial = 2.0, rate = 0.0 }
[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"
[[unilateral]]
name = "sphere"
gap = "(x^2 + y^2 - R^2)/(2*R)"
)toml";
    const auto result = eomc::host::simulate(request(test_support::kernel_of(scene), 1.0));
    BOOST_REQUIRE(result.contact_events.size() >= 2u);
    const auto& contact = result.contact_events[0];
    BOOST_TEST(contact.kind == "contact");
    BOOST_TEST(contact.t == 0.0);
    BOOST_TEST(contact.lambda == 9.81 - 1.5 * 1.5 / 2.0, boost::test_tools::tolerance(1e-12));
    const auto& separation = result.contact_events[1];
    BOOST_TEST(separation.kind == "separation");
    BOOST_TEST(std::abs(separation.t - 0.717367168216632) <= 1e-10);
    // Free flight after it: no further contact event, and the state at t = 1 is off the sphere.
    BOOST_TEST(result.contact_events.size() == 2u);
    BOOST_TEST(result.value("x") * result.value("x") + result.value("y") * result.value("y") > 4.0);
}
