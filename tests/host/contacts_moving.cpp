// Moving (rheonomic) unilateral gaps f(q, t) ≥ 0 end to end, through eomc simulate with both contact
// drivers: the kernel exports w = ∂f/∂t (ḟ = W u + w) and the bias of f̈ = W q̈ + b holds ∂²f/∂t² and
// 2 ∂²f/∂q∂t q̇. Known answers: a ball over a floor rising at constant speed (Galilean invariance:
// in the floor's frame it is the bouncing ball), over a floor of constant acceleration (the ball
// sees g + a), and on a sinusoidally driven table on its period-1 orbit (Holmes, "The dynamics of
// repeated impacts with a sinusoidally vibrating table", J. Sound Vib. 84(2) (1982) 173–189).
// Newton's law acts on the rates of the constraints (Mei, Special Topics in Analytical Mechanics,
// §6.5): ḟ⁺ = −e ḟ⁻, so in the ground frame v⁺ = V − e (v⁻ − V) for a floor moving at V.
#define BOOST_TEST_MODULE simulate_contacts_moving
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/unilateral/unilateral.hpp"

#include "scenes.hpp"
#include "simulation.hpp"

namespace {

constexpr double g = 9.81, e_ball = 0.7, h0 = 2.0, m = 1.5;

// The ball (m, e) dropped from rest at h0 over the floor of gap `gap`.
std::string ball_over(const std::string& gap, const std::string& extra_parameters) {
    return R"toml([scene]
name = "ball_moving_floor"
[parameters]
m = 1.5
g = 9.81
e = 0.7
)toml" + extra_parameters +
           R"toml(
[coordinates]
y = { initial = 2.0, rate = 0.0 }
[lagrangian]
T = "m*y_dot^2/2"
V = "m*g*y"
[[unilateral]]
name = "floor"
gap = ")toml" + gap + R"toml("
restitution = "e"
)toml";
}

eomc::host::SimulationRequest request_for(const std::string& scene, double t_end) {
    auto r = test_support::simulation_request(test_support::kernel_of(scene), t_end);
    r.rtol = 1e-12;
    r.atol = 1e-14;
    return r;
}

std::vector<const eomc::host::ContactEventReport*> events_of(const eomc::host::SimulationResult& result,
                                                             const std::string& kind) {
    std::vector<const eomc::host::ContactEventReport*> out;
    for (const auto& e : result.contact_events)
        if (e.kind == kind) out.push_back(&e);
    return out;
}

// The relative motion z = y − s(t) of a floor s = V t + a t²/2: the bouncing ball under G = g + a
// from z = h0 with ż = −V. First impact t1 = (−V + s1)/G with the relative impact speed
// s1 = √(V² + 2 G h0); then flights 2 e^k s1/G; the Zeno point t1 + 2 e s1/(G (1 − e)).
struct Relative {
    double V, a, G, s1, t1;
    Relative(double V_, double a_) : V(V_), a(a_), G(g + a_), s1(std::sqrt(V_ * V_ + 2 * (g + a_) * h0)) {
        t1 = (-V + s1) / G;
    }
    double impact(int k) const {
        double t = t1;
        for (int j = 1; j < k; ++j) t += 2 * std::pow(e_ball, j) * s1 / G;
        return t;
    }
    double zeno() const { return t1 + 2 * e_ball * s1 / (G * (1 - e_ball)); }
    double floor_speed(double t) const { return V + a * t; }
};

// The event-driven run at rtol 1e-12: the flights are quadratic in t (dopri5 exact to round-off), so
// each impact time carries the tolerance over its impact speed (≥ e⁴ s1 ≈ 0.24 s1 here) plus Brent's
// bracket, growing at most by (1 + 2e) per impact: 1e-9 bounds five impacts with a wide margin.
void check_event_driven(const Relative& rel, const eomc::host::SimulationResult& result, double t_end) {
    const auto impacts = events_of(result, "impact");
    // Every impact the integration resolves (intervals above 100 impact-time errors), then Zeno;
    // the first five in detail, the rest in order before the Zeno point.
    BOOST_REQUIRE(impacts.size() > 5u);
    for (std::size_t k = 1; k < impacts.size(); ++k) {
        BOOST_TEST(impacts[k]->t > impacts[k - 1]->t);
        BOOST_TEST(impacts[k]->t < rel.zeno());
    }
    for (int k = 1; k <= 5; ++k) {
        const auto& ev = *impacts[std::size_t(k - 1)];
        BOOST_TEST(std::abs(ev.t - rel.impact(k)) <= 1e-9);
        const double speed = std::pow(e_ball, k - 1) * rel.s1;  // relative, = −ḟ⁻
        BOOST_TEST(std::abs(ev.rate_before + speed) <= 1e-8);
        BOOST_TEST(std::abs(ev.rate_after - e_ball * speed) <= 1e-8);
        // Ground frame: v⁻ = ḟ⁻ + V(t), v⁺ = V − e (v⁻ − V); ΔT = ½ m (v⁺² − v⁻²) is what Carnot's
        // theorem in the floor's frame less the floor's work P w predicts.
        const double Vt = rel.floor_speed(ev.t), v_minus = ev.rate_before + Vt, v_plus = Vt - e_ball * (v_minus - Vt);
        BOOST_TEST(ev.energy_change == 0.5 * m * (v_plus * v_plus - v_minus * v_minus),
                   boost::test_tools::tolerance(1e-8));
        BOOST_TEST(std::abs(ev.energy_change - ev.carnot) <= 1e-9 * m * rel.s1 * rel.s1);
    }
    const auto zeno = events_of(result, "zeno");
    BOOST_REQUIRE(zeno.size() == 1u);
    BOOST_TEST(std::abs(zeno[0]->t - rel.zeno()) <= zeno[0]->extrapolation_error + 1e-8);
    // Riding the floor: y = s(t), ẏ = ṡ(t) (the projection), λ = m (g + a).
    const double s = rel.V * t_end + 0.5 * rel.a * t_end * t_end;
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(std::abs(result.value("y") - s) <= 1e-9 * (1 + s));
    BOOST_TEST(std::abs(result.value("y_dot") - rel.floor_speed(t_end)) <= 1e-9 * (1 + rel.floor_speed(t_end)));
    BOOST_TEST(result.value("lambda_floor") == m * rel.G, boost::test_tools::tolerance(1e-10));
}

}  // namespace

// A floor rising at v_p = 1.5 (gap y − v_p t), event-driven.
BOOST_AUTO_TEST_CASE(floor_at_constant_speed_event_driven) {
    const Relative rel(1.5, 0.0);
    check_event_driven(rel, eomc::host::simulate(request_for(ball_over("y - vp*t", "vp = 1.5"), 6.0)), 6.0);
}

// A floor accelerating up at a = 3 (gap y − a t²/2): the ball sees g + a; from relative rest the
// Zeno point is t∞ = t1 (1 + e)/(1 − e).
BOOST_AUTO_TEST_CASE(floor_at_constant_acceleration_event_driven) {
    const Relative rel(0.0, 3.0);
    BOOST_TEST(rel.zeno() == rel.t1 * (1 + e_ball) / (1 - e_ball), boost::test_tools::tolerance(1e-14));
    check_event_driven(rel, eomc::host::simulate(request_for(ball_over("y - a*t^2/2", "a = 3.0"), 4.0)), 4.0);
}

// Moreau–Jean (θ = 1/2, h = 1e-4) on both floors: impact times to O(h) (within 2h, the error of
// each adding to the next flight at most by 2e), the ground-frame rebound v⁺ = V − e (v⁻ − V) to
// g h per step of that; at the end the ball rides the floor, ẏ = ṡ(t_end) to round-off (W u + w = 0
// imposed on each step's end velocity), y within O(h) of s, λ = P/h = m (g + a) to O(h).
BOOST_AUTO_TEST_CASE(moving_floors_moreau_jean) {
    struct Case {
        Relative rel;
        std::string gap, parameter;
        double t_end;
    };
    for (const Case& c : {Case{Relative(1.5, 0.0), "y - vp*t", "vp = 1.5", 6.0},
                          Case{Relative(0.0, 3.0), "y - a*t^2/2", "a = 3.0", 4.0}}) {
        auto r = request_for(ball_over(c.gap, c.parameter), c.t_end);
        r.contact_method = "moreau_jean";
        r.step = 1e-4;
        const auto result = eomc::host::simulate(r);
        const auto impacts = events_of(result, "impact");
        BOOST_REQUIRE(impacts.size() >= 4u);
        for (int k = 1; k <= 4; ++k) {
            const auto& ev = *impacts[std::size_t(k - 1)];
            const double bound = 2 * r.step * std::pow(1 + 2 * e_ball, k);
            BOOST_TEST(std::abs(ev.t - c.rel.impact(k)) <= bound);
            BOOST_TEST(std::abs(ev.rate_after - std::pow(e_ball, k) * c.rel.s1) <= 2 * c.rel.G * bound);
        }
        BOOST_TEST(result.contacts[0].active);
        const double s = c.rel.V * c.t_end + 0.5 * c.rel.a * c.t_end * c.t_end;
        BOOST_TEST(result.value("y_dot") == c.rel.floor_speed(c.t_end), boost::test_tools::tolerance(1e-12));
        BOOST_TEST(std::abs(result.value("y") - s) <= 1e-3);
        BOOST_TEST(std::abs(result.value("lambda_floor") - m * c.rel.G) <= 10 * m * c.rel.G * r.step);
    }
}

// scenes/ball_vibrating_table.toml: the table at A sin(ω t), T = 2π/ω. The period-n orbit (here
// n = 1): the ball leaves at v⁺ and lands after n T where the table is back at the same height, so
// v⁺ = g n T/2 and v⁻ = −v⁺. Newton's law on the relative rate, v⁺ − V = −e (v⁻ − V) with the table's
// velocity V = A ω cos φ*, gives v⁺ (1 − e) = (1 + e) V, i.e.
//     cos φ* = g n T (1 − e) / (2 (1 + e) A ω)
// for the impact phase φ* = ω t mod 2π. With g = 9.81, T = 0.5, e = 0.5, A ω = 1: cos φ* = 0.8175.
// Stability (Holmes's map φ' = φ + v, v' = e v + γ cos φ', γ = 2 (1 + e) A ω²/g, v = 2 ω v⁺/g,
// the table's displacement neglected in the flight): the Jacobian has det e and trace
// 1 + e − γ sin φ*, so the orbit is stable iff 0 < γ sin φ* < 2 (1 + e), i.e. 0 < A ω² sin φ* < g
// (the table decelerating at impact, less than g): here 7.24 < 9.81, the root with sin φ* > 0.
BOOST_AUTO_TEST_CASE(vibrating_table_period_one_orbit) {
    constexpr double pi = std::numbers::pi, e = 0.5, omega = 4 * pi, A = 1 / omega, T = 2 * pi / omega;
    const double cos_phi = g * T * (1 - e) / (2 * (1 + e) * A * omega), phi = std::acos(cos_phi);
    BOOST_TEST(cos_phi == 0.8175, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(A * omega * omega * std::sin(phi) < g);  // stable (above)
    const double v_plus = g * T / 2, V = A * omega * cos_phi, t_star = phi / omega;
    auto r = test_support::simulation_request(
        test_support::kernel_of(test_support::bundled_scene("ball_vibrating_table")), 5.0);
    r.rtol = 1e-12;
    r.atol = 1e-14;
    // Event-driven: ten impacts at t* + k T. The flights are quadratic (dopri5 exact to round-off) and
    // the gap's sine is evaluated, not integrated, so each time carries the tolerance over the impact
    // speed 3.27 and Brent's bracket; the orbit is stable, so the errors do not grow: 1e-9.
    {
        const auto result = eomc::host::simulate(r);
        const auto impacts = events_of(result, "impact");
        BOOST_REQUIRE(impacts.size() == 10u);
        for (std::size_t k = 0; k < impacts.size(); ++k) {
            const auto& ev = *impacts[k];
            BOOST_TEST(std::abs(ev.t - (t_star + double(k) * T)) <= 1e-9);
            BOOST_TEST(std::abs(std::remainder(omega * ev.t - phi, 2 * pi)) <= omega * 1e-9);
            BOOST_TEST(std::abs(ev.rate_before + (v_plus + V)) <= 1e-8);  // ḟ⁻ = v⁻ − V
            BOOST_TEST(std::abs(ev.rate_after - (v_plus - V)) <= 1e-8);   // ḟ⁺ = v⁺ − V = −e ḟ⁻
            BOOST_TEST(std::abs(ev.energy_change) <= 1e-10);               // v⁺ = −v⁻: no loss over the impact
            BOOST_TEST(std::abs(ev.energy_change - ev.carnot) <= 1e-10);
        }
        BOOST_TEST(events_of(result, "zeno").empty());
    }
    // Moreau–Jean (h = 1e-4): each impact within a few steps of t* + k T (the stable orbit keeps the
    // O(h) errors from adding up), the rebound's relative rate to g h per step of timing error.
    {
        r.contact_method = "moreau_jean";
        r.step = 1e-4;
        const auto result = eomc::host::simulate(r);
        const auto impacts = events_of(result, "impact");
        BOOST_REQUIRE(impacts.size() == 10u);
        for (std::size_t k = 0; k < impacts.size(); ++k) {
            BOOST_TEST(std::abs(impacts[k]->t - (t_star + double(k) * T)) <= 3 * r.step);
            BOOST_TEST(std::abs(impacts[k]->rate_after - (v_plus - V)) <= 30 * g * r.step);
        }
    }
}

// The bias of a gap that depends on t and q nonlinearly, f = y − A sin(ω t) cos x + c t x², against a
// central second difference of f along a smooth motion x(t), y(t): f̈ = W q̈ + b. The difference's
// error is h² f⁗/12 (|f⁗| ≲ A ω⁴ + O(1) ≈ 15 here, h = 1e-3: ~1e-6) plus the round-off 4 ε |f| / h²
// (~1e-9): 1e-5 bounds both. Also the kernel's w = ∂f/∂t against the first difference of f with q
// frozen, and ḟ = W q̇ + w along the motion (errors h² f‴/6 ~ 1e-6).
BOOST_AUTO_TEST_CASE(bias_and_time_rate_of_a_moving_gap) {
    const std::string scene = R"toml([scene]
name = "moving_gap_rows"
[parameters]
A = 0.3
omega = 2.5
c = 0.7
[coordinates]
x = { initial = 0.1 }
y = { initial = 1.0 }
[lagrangian]
T = "x_dot^2/2 + y_dot^2/2"
V = "0"
[[unilateral]]
name = "wall"
gap = "y - A*sin(omega*t)*cos(x) + c*t*x^2"
restitution = "0.5"
)toml";
    const auto model = test_support::model_of(scene);
    const auto rows = eomc::mechanics::unilateral_rows(model);
    BOOST_REQUIRE(rows.size() == 1u);
    const auto& row = rows[0].row;
    const auto& X = model.coordinates[0];
    const auto& Y = model.coordinates[1];
    GiNaC::exmap values;
    for (const auto& p : model.parameters) values[p.symbol] = p.name == "A" ? 0.3 : p.name == "omega" ? 2.5 : 0.7;
    const auto motion = [](double t, double& x, double& xd, double& xdd, double& y, double& yd, double& ydd) {
        x = 0.4 * std::sin(1.3 * t) + 0.1;
        xd = 0.52 * std::cos(1.3 * t);
        xdd = -0.676 * std::sin(1.3 * t);
        y = 0.5 * std::cos(0.7 * t);
        yd = -0.35 * std::sin(0.7 * t);
        ydd = -0.245 * std::cos(0.7 * t);
    };
    const auto eval = [&](const GiNaC::ex& e, double t, double x, double xd, double y, double yd) {
        GiNaC::exmap at = values;
        at[model.t] = t;
        at[X.q] = x;
        at[X.q_dot] = xd;
        at[Y.q] = y;
        at[Y.q_dot] = yd;
        return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(at))).to_double();
    };
    const auto f_along = [&](double t) {
        double x, xd, xdd, y, yd, ydd;
        motion(t, x, xd, xdd, y, yd, ydd);
        return eval(row.position, t, x, 0, y, 0);
    };
    // The lowered kernel's w (its CSE temporaries substituted back).
    const auto ir = eomc::codegen::lower(model, eomc::mechanics::derive(model));
    BOOST_REQUIRE(ir.contact_time_rates.outputs.size() == 1u);
    GiNaC::ex w = ir.contact_time_rates.outputs[0];
    for (auto it = ir.contact_time_rates.temporaries.rbegin(); it != ir.contact_time_rates.temporaries.rend(); ++it)
        w = w.subs(it->symbol == it->value);
    const double h = 1e-3;
    for (double t : {0.3, 1.1, 2.7}) {
        double x, xd, xdd, y, yd, ydd;
        motion(t, x, xd, xdd, y, yd, ydd);
        const double fdd = (f_along(t + h) - 2 * f_along(t) + f_along(t - h)) / (h * h);
        const double model_fdd = eval(row.W[0], t, x, xd, y, yd) * xdd + eval(row.W[1], t, x, xd, y, yd) * ydd +
                                 eval(row.bias, t, x, xd, y, yd);
        BOOST_TEST(std::abs(fdd - model_fdd) <= 1e-5);
        const double ft = (eval(row.position, t + h, x, 0, y, 0) - eval(row.position, t - h, x, 0, y, 0)) / (2 * h);
        BOOST_TEST(std::abs(eval(w, t, x, xd, y, yd) - ft) <= 1e-5);
        // and ḟ = W q̇ + w along the motion
        const double fd = (f_along(t + h) - f_along(t - h)) / (2 * h);
        BOOST_TEST(std::abs(eval(row.W[0], t, x, xd, y, yd) * xd + eval(row.W[1], t, x, xd, y, yd) * yd +
                            eval(w, t, x, xd, y, yd) - fd) <= 1e-5);
    }
    // A fixed gap's kernel carries no time rates (its bytes unchanged; the runtime takes w = 0).
    const auto fixed = test_support::bundled_model("bouncing_ball");
    BOOST_TEST(eomc::codegen::lower(fixed, eomc::mechanics::derive(fixed)).contact_time_rates.outputs.empty());
}
