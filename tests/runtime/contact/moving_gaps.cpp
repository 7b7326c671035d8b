// Moving (rheonomic) gaps g(t, q) ≥ 0 in the contact runtime (event_driven.hpp, moreau_jean.hpp,
// impact.hpp): the rate of a gap is ġ = W u + w with w = ∂g/∂t. A ball (M = m, f = −m g) above a
// floor driven in time; closed forms from Galilean invariance (a floor at constant speed: in its
// frame the ball bounces as on a fixed floor) and from the equivalence principle (a floor of constant
// acceleration a: in its frame gravity is g + a). Mei, Special Topics in Analytical Mechanics, ch. 6
// (§6.5, Newton's law on the rates of the constraints).
#define BOOST_TEST_MODULE runtime_moving_gaps
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/contact/event_driven.hpp"
#include "eomc/runtime/contact/impact.hpp"
#include "eomc/runtime/contact/moreau_jean.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"

namespace rt = eomc::runtime;
namespace ct = eomc::runtime::contact;
using Vec = ct::Vector<double>;
using Mat = ct::Matrix<double>;

namespace {

constexpr double grav = 9.81, mass = 2.0, e_ball = 0.7, h0 = 2.0;
const double eps = std::numeric_limits<double>::epsilon();
const rt::Tolerances tight{1e-12, 1e-14};

// The floor at height s(t) = c1 t + c2 t²/2: gap y − s(t), w = −ṡ, b = −s̈.
struct Floor {
  double speed = 0, acceleration = 0;
  double s(double t) const { return speed * t + 0.5 * acceleration * t * t; }
  double sdot(double t) const { return speed + acceleration * t; }
};

ct::ContactSystem<double> ball_over(const Floor& fl, bool with_rates = true) {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{e_ball, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = mass; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f[0] = -mass * grav; };
  sys.gaps = [fl](double t, const Vec& q, const Vec&, Vec& g) { g[0] = q[0] - fl.s(t); };
  sys.rows = [fl](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    b[0] = -fl.acceleration;
  };
  if (with_rates) sys.time_rates = [fl](double t, const Vec&, Vec& w) { w[0] = -fl.sdot(t); };
  return sys;
}

std::vector<ct::ContactEvent<double>> of_kind(const ct::EventDrivenOutcome<double>& out, ct::ContactEventKind kind) {
  std::vector<ct::ContactEvent<double>> v;
  for (const auto& e : out.events)
    if (e.kind == kind) v.push_back(e);
  return v;
}

ct::EventDrivenOutcome<double> run(const ct::ContactSystem<double>& sys, rt::State<double>& x, double t0, double t1,
                                   double& lambda_end) {
  rt::Dopri5<double> stepper;
  auto out = ct::integrate_event_driven(stepper, sys, x, t0, t1, tight,
                                        [&](double, const rt::State<double>&, const Vec& l, const std::vector<bool>&) {
                                          lambda_end = l[0];
                                        });
  return out;
}

// The relative motion z = y − s(t) is the bouncing ball under gravity G = g + a from height h0 with
// speed ż0 = −c1: first impact at t1 = (ż0 + √(ż0² + 2 G h0))/G, relative impact speed
// s1 = √(ż0² + 2 G h0), then flights 2 e^k s1 / G. Zeno at t1 + 2 e s1 / (G (1 − e)).
struct Relative {
  double G, t1, s1;
  Relative(const Floor& fl) : G(grav + fl.acceleration) {
    const double zdot0 = -fl.speed;
    s1 = std::sqrt(zdot0 * zdot0 + 2 * G * h0);
    t1 = (zdot0 + s1) / G;
  }
  double impact(int k) const {  // k = 1, 2, …
    double t = t1;
    for (int j = 1; j < k; ++j) t += 2 * std::pow(e_ball, j) * s1 / G;
    return t;
  }
  double zeno() const { return t1 + 2 * e_ball * s1 / (G * (1 - e_ball)); }
};

// The bound on the k-th impact time as in event_driven.cpp's ball: the flights are quadratic in t
// (dopri5 exact to round-off), each impact carries the tolerance over the impact speed plus Brent's
// 8 ε t, and an error dt moves the next flight by 2 e dt.
double time_bound(const Relative& r, double t_last, int count) {
  const double per = 8 * eps * t_last + (tight.rtol * (h0 + 10) + tight.atol) / (std::pow(e_ball, count - 1) * r.s1);
  double bound = 0;
  for (int k = 0; k < count; ++k) bound = bound * (1 + 2 * e_ball) + per;
  return bound;
}

void check_floor(const Floor& fl, double t_end) {
  const Relative rel(fl);
  rt::State<double> x{h0, 0.0};
  double lambda = 0;
  const auto out = run(ball_over(fl), x, 0.0, t_end, lambda);
  const auto impacts = of_kind(out, ct::ContactEventKind::impact);
  // Every impact the integration resolves, then Zeno: the driver extrapolates once an interval
  // 2 e^(k−1) s1 / G falls below 100 impact-time errors, 8 ε t_k + (rtol (1 + |y|) + atol) /
  // (e^(k−1) s1) (event_driven.hpp); predicted here from the closed form, to one impact.
  std::size_t predicted = 5;
  for (int k = 2;; ++k) {
    const double speed = std::pow(e_ball, k - 1) * rel.s1, t_k = rel.impact(k);
    const double sigma = 8 * eps * t_k + (tight.rtol * (1 + std::abs(fl.s(t_k))) + tight.atol) / speed;
    if (2 * std::pow(e_ball, k - 1) * rel.s1 / rel.G <= 100 * sigma) {
      predicted = std::max<std::size_t>(predicted, std::size_t(k));
      break;
    }
  }
  BOOST_TEST_MESSAGE(impacts.size() << " impacts before Zeno, predicted " << predicted);
  // Not one resolvable impact skipped; after the last the extrapolation may wait for its own error
  // estimate to stop falling (a few impacts more).
  BOOST_REQUIRE(impacts.size() + 1 >= predicted);
  BOOST_REQUIRE(impacts.size() <= predicted + 3);
  for (int k = 1; k <= int(impacts.size()); ++k) {
    const auto& ev = impacts[std::size_t(k - 1)];
    BOOST_TEST(std::abs(ev.t - rel.impact(k)) <= time_bound(rel, ev.t, k));
    // The relative impact speed e^(k−1) s1 and Newton's law on it, ġ⁺ = −e ġ⁻ (the ground-frame
    // rebound v⁺ = ṡ − e (v⁻ − ṡ)): rates carry the time error × G besides round-off.
    const double speed = std::pow(e_ball, k - 1) * rel.s1, tol = 1e-9 * rel.s1;
    BOOST_TEST(std::abs(ev.rate_before + speed) <= tol);
    BOOST_TEST(std::abs(ev.rate_after - e_ball * speed) <= tol);
    // ΔT = Carnot's loss in the floor's frame − P w (the work of the moving floor's impulse).
    BOOST_TEST(std::abs(ev.energy_change - ev.carnot) <= 1e-9 * mass * rel.s1 * rel.s1);
    BOOST_TEST(std::abs(ev.impulse - mass * (1 + e_ball) * speed) <= mass * (1 + e_ball) * tol);
  }
  const auto zeno = of_kind(out, ct::ContactEventKind::zeno);
  BOOST_REQUIRE(zeno.size() == 1u);
  // The Zeno extrapolation's own estimate bounds its error (event_driven.hpp), plus the times'.
  BOOST_TEST(std::abs(zeno[0].t - rel.zeno()) <= zeno[0].extrapolation_error + 1e-8);
  // The ratio comes from intervals of about 100 impact-time errors: it carries their relative
  // error, 4 σ / Δt ≤ 0.04, besides zeno_rtol (1 − e).
  BOOST_TEST(std::abs(zeno[0].ratio - e_ball) <= 0.04 + 1e-2 * (1 - e_ball));
  // Riding the floor: y = s(t), ẏ = ṡ(t) (projected), λ = m (g + a) (from m ÿ = −m g + λ, ÿ = a).
  BOOST_TEST(out.active[0]);
  BOOST_TEST(std::abs(x[0] - fl.s(t_end)) <= 1e-9 * (1 + std::abs(fl.s(t_end))));
  BOOST_TEST(std::abs(x[1] - fl.sdot(t_end)) <= 1e-9 * (1 + std::abs(fl.sdot(t_end))));
  BOOST_TEST(lambda == mass * (grav + fl.acceleration), boost::test_tools::tolerance(1e-10));
}

}  // namespace

// A floor rising at v_p = 1.5: Galilean invariance.
BOOST_AUTO_TEST_CASE(floor_at_constant_speed) { check_floor({1.5, 0.0}, 6.0); }

// A floor accelerating upward at a = 3: the ball sees g + a; t∞ = t1 (1 + e)/(1 − e) (from rest
// relative to the floor at t = 0).
BOOST_AUTO_TEST_CASE(floor_at_constant_acceleration) {
  const Floor fl{0.0, 3.0};
  const Relative rel(fl);
  BOOST_TEST(rel.zeno() == rel.t1 * (1 + e_ball) / (1 - e_ball), boost::test_tools::tolerance(1e-14));
  check_floor(fl, 4.0);
}

// Without the time rate the driver would treat the floor as fixed in the impact law (the bug this
// guards): the first rebound in the ground frame would be −e v⁻ instead of v_p − e (v⁻ − v_p).
BOOST_AUTO_TEST_CASE(time_rate_changes_the_rebound) {
  const Floor fl{1.5, 0.0};
  rt::State<double> x{h0, 0.0};
  double lambda = 0;
  const auto with = run(ball_over(fl), x, 0.0, 0.8, lambda);
  rt::State<double> y{h0, 0.0};
  const auto without = run(ball_over(fl, false), y, 0.0, 0.8, lambda);
  const auto a = of_kind(with, ct::ContactEventKind::impact), b = of_kind(without, ct::ContactEventKind::impact);
  BOOST_REQUIRE(a.size() == 1u);
  BOOST_REQUIRE(b.size() == 1u);
  const double v_minus = -grav * a[0].t;  // ground frame, from rest
  BOOST_TEST(x[1] + grav * (0.8 - a[0].t) == 1.5 - e_ball * (v_minus - 1.5), boost::test_tools::tolerance(1e-9));
  BOOST_TEST(std::abs(y[1] + grav * (0.8 - b[0].t) - (-e_ball * v_minus)) <= 1e-9);
}

// impact.hpp with w: one contact, ḟ⁻ = W u⁻ + w, P = −(1 + e) ḟ⁻ / G; the sequential law agrees for
// one contact; the energy balance includes −P w.
BOOST_AUTO_TEST_CASE(newton_impact_with_time_rate) {
  rt::LcpMatrix<double> M(1, 1), W(1, 1);
  M << mass;
  W << 1.0;
  rt::LcpVector<double> e(1), u(1), w(1);
  e << e_ball;
  u << -3.0;
  w << -1.5;  // a floor rising at 1.5
  for (const auto& r : {rt::newton_impact<double>(M, W, e, u, w), rt::sequential_impacts<double>(M, W, e, u, w)}) {
    BOOST_TEST(r.u_plus[0] == 1.5 - e_ball * (-3.0 - 1.5), boost::test_tools::tolerance(1e-15));
    BOOST_TEST(r.P[0] == mass * (1 + e_ball) * 4.5, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(r.kinetic_energy_after - r.kinetic_energy_before == r.carnot_prediction,
               boost::test_tools::tolerance(1e-13));
  }
}

// Moreau–Jean (θ = 1/2, h = 1e-4) on the floor rising at constant speed: the impacts are resolved to
// O(h) in time (a few steps), the rebound to the velocity error of that (G h per step) and the end
// state rides the floor with u = v_p exactly (W u + w = 0 imposed on every step's end velocity) and
// the gap O(h) (the law acts on velocities).
BOOST_AUTO_TEST_CASE(moreau_jean_floor_at_constant_speed) {
  const Floor fl{1.5, 0.0};
  const Relative rel(fl);
  const double h = 1e-4;
  rt::LcpVector<double> q(1), u(1), e(1);
  q << h0;
  u << 0.0;
  e << e_ball;
  rt::MoreauJeanOptions<double> options;
  options.time_rates = [fl](double t, const rt::LcpVector<double>&) {
    return rt::LcpVector<double>(rt::LcpVector<double>::Constant(1, -fl.sdot(t)));
  };
  std::vector<double> impact_times, rebounds;
  double u_prev = 0.0;
  rt::integrate_moreau_jean<double>(
      [](double, const rt::LcpVector<double>&) { return rt::LcpMatrix<double>::Constant(1, 1, mass); },
      [](double, const rt::LcpVector<double>&, const rt::LcpVector<double>&) {
        return rt::LcpVector<double>::Constant(1, -mass * grav);
      },
      [fl](double t, const rt::LcpVector<double>& qq) { return rt::LcpVector<double>::Constant(1, qq[0] - fl.s(t)); },
      [](double, const rt::LcpVector<double>&) { return rt::LcpMatrix<double>::Constant(1, 1, 1.0); }, e, 0.0, 6.0,
      h, q, u,
      [&](double t, const rt::LcpVector<double>&, const rt::LcpVector<double>& un, const rt::MoreauJeanStep<double>& s) {
        // An impact: approaching before, leaving after by more than the forces change in a few steps.
        if (s.P[0] > 0 && u_prev - fl.speed < -10 * grav * h && un[0] - fl.speed > 10 * grav * h) {
          impact_times.push_back(t);
          rebounds.push_back(un[0]);
        }
        u_prev = un[0];
      },
      options);
  BOOST_REQUIRE(impact_times.size() >= 4u);
  for (int k = 1; k <= 4; ++k) {
    // Each impact time O(h) (2 h), the errors adding up with the flights (≤ (1 + 2e) growth).
    BOOST_TEST(std::abs(impact_times[std::size_t(k - 1)] - rel.impact(k)) <= 2 * h * std::pow(1 + 2 * e_ball, k));
    // v⁺ = v_p + e × relative speed, to G h per step of timing error.
    const double expected = fl.speed + e_ball * std::pow(e_ball, k - 1) * rel.s1;
    BOOST_TEST(std::abs(rebounds[std::size_t(k - 1)] - expected) <= 2 * grav * h * std::pow(1 + 2 * e_ball, k));
  }
  BOOST_TEST(u[0] == fl.speed, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(std::abs(q[0] - fl.s(6.0)) <= 10 * grav * h * h + 1e-3);
}
