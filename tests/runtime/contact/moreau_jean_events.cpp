// Moreau–Jean on a ContactSystem (contact/moreau_jean.hpp) reports its own events, as the
// event-driven driver does: the bouncing ball's impacts (times, rates, impulses, Carnot's loss
// against the measured energy change), its contact at the Zeno point with λ = m g; a block pressed
// on a floor by gravity and lifted by a growing force separates at t = m g / a; a kinematic row
// takes no impact.
#define BOOST_TEST_MODULE runtime_moreau_jean_events
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/contact/moreau_jean.hpp"

namespace rt = eomc::runtime;
namespace rc = eomc::runtime::contact;

namespace {

using Vec = rc::Vector<double>;
using Mat = rc::Matrix<double>;

const double eps = std::numeric_limits<double>::epsilon();

// One particle of mass m on the line, a floor y ≥ 0 (restitution e) and the force `force(t)`.
template <class Force>
rc::ContactSystem<double> particle_on_floor(double m, double e, Force force, rc::GapLevel level = rc::GapLevel::position) {
  rc::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts.push_back({e, level});
  sys.mass = [m](double, const Vec&, Mat& M) { M(0, 0) = m; };
  sys.force = [force](double t, const Vec&, const Vec&, Vec& f) { f[0] = force(t); };
  sys.gaps = [level](double, const Vec& q, const Vec& u, Vec& g) {
    g[0] = level == rc::GapLevel::position ? q[0] : u[0];
  };
  sys.rows = [](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    b[0] = 0.0;
  };
  return sys;
}

struct Recorded {
  std::vector<rc::ContactEvent<double>> events;
  std::vector<double> times;
  double last_lambda = 0.0;
  bool last_active = false;
  int observed_after_event = 0;  // observer calls that saw the state after each event's step
};

Recorded run(const rc::ContactSystem<double>& sys, double y0, double v0, double t_end, double h, double theta = 0.5) {
  Recorded r;
  rt::State<double> x{y0, v0};
  std::size_t seen = 0;
  rt::integrate_moreau_jean<double>(
      sys, 0.0, t_end, h, theta, x,
      [&](double t, const rt::State<double>&, const Vec& lambda, const std::vector<bool>& active) {
        r.times.push_back(t);
        r.last_lambda = lambda[0];
        r.last_active = active[0];
        if (r.events.size() > seen) {
          for (std::size_t i = seen; i < r.events.size(); ++i) BOOST_TEST(r.events[i].t == t);
          seen = r.events.size();
          ++r.observed_after_event;
        }
      },
      [&](const rc::ContactEvent<double>& e) { r.events.push_back(e); });
  return r;
}

}  // namespace

// The bouncing ball, h0 = 2, g = 9.81, e = 0.7, m = 2: the k-th impact at
// t_k = t_1 (1 + 2e (1 − e^(k−1)) / (1 − e)), t_1 = √(2 h0 / g), with the speed v_k = g t_1 e^(k−1).
// Over an impact step Moreau–Jean's law gives u⁺ = −e u⁻ exactly (Newton's law on the step's start
// velocity), P = m((1 + e) v − g h) and T⁺ − T⁻ = −½ m (1 − e²) v²; Carnot's loss of the impulsive
// Δu = P/m differs from that by m (1 − e) v g h at most (expanding ((1 + e) v − g h)²). The step
// holding the impact is resolved to h: |t − t_k| ≤ h while the flights are long (before the Zeno
// point t_∞ = t_1 (1 + e)/(1 − e) the intervals shrink to below h).
BOOST_AUTO_TEST_CASE(bouncing_ball_impacts_then_rest_with_lambda_mg) {
  const double g = 9.81, h0 = 2.0, e = 0.7, m = 2.0, h = 1e-4;
  const auto sys = particle_on_floor(m, e, [&](double) { return -m * g; });
  const Recorded r = run(sys, h0, 0.0, 5.0, h);
  const double t1 = std::sqrt(2 * h0 / g), zeno = t1 * (1 + e) / (1 - e);

  int k = 0;
  for (const auto& ev : r.events) {
    if (ev.kind != rc::ContactEventKind::impact) continue;
    ++k;
    const double tk = t1 * (1 + 2 * e * (1 - std::pow(e, k - 1)) / (1 - e)), vk = g * t1 * std::pow(e, k - 1);
    BOOST_TEST_CONTEXT("impact " << k << " at " << ev.t) {
      BOOST_TEST(ev.contact == 0u);
      if (k <= 3) {
        // The impact is found in the step that starts within h/2 of the floor, or in the next
        // (1.5 h), and each bounce shifts the next flight by as much: k 1.5 h. The speed at the
        // step's start is g · 1.5 h off, each bounce carrying the error on (times e < 1).
        BOOST_TEST(std::abs(ev.t - tk) <= 1.5 * k * h * (1 + 1e-9));
        BOOST_TEST(std::abs(-ev.rate_before - vk) <= 1.5 * g * h * k * (1 + 1e-9));
      }
      BOOST_TEST(std::abs(ev.rate_after + e * ev.rate_before) <= 64 * eps * std::abs(ev.rate_before));
      const double v = -ev.rate_before;
      BOOST_TEST(std::abs(ev.impulse - m * ((1 + e) * v - g * h)) <= 64 * eps * m * v);
      BOOST_TEST(std::abs(ev.energy_change + 0.5 * m * (1 - e * e) * v * v) <= 64 * eps * m * v * v);
      BOOST_TEST(ev.carnot < 0.0);
      BOOST_TEST(std::abs(ev.carnot - ev.energy_change) <= m * (1 - e) * v * g * h * (1 + 1e-9));
    }
  }
  BOOST_TEST(k >= 10);  // the long flights, then the accumulation
  // The last event is the contact phase near the Zeno point: the bounces end where they are
  // slower than twice what gravity changes in a step (2 g h), flights of 4 h, so within a few
  // steps of t_∞ but for the O(k h) drift of the impact times; checked against t_∞ + 0.01 (100
  // steps) and the tenth impact (the contact comes after the long flights).
  BOOST_TEST_REQUIRE(!r.events.empty());
  const auto& last = r.events.back();
  BOOST_TEST((last.kind == rc::ContactEventKind::contact));
  BOOST_TEST_MESSAGE("contact at " << last.t << ", Zeno point " << zeno);
  BOOST_TEST(last.t <= zeno + 0.01);
  BOOST_TEST(last.t >= t1 * (1 + 2 * e * (1 - std::pow(e, 9)) / (1 - e)));
  // At rest the step's impulse carries the weight: P = m g h, λ = P/h = m g.
  BOOST_TEST(r.last_active);
  BOOST_TEST(std::abs(r.last_lambda - m * g) <= 64 * eps * m * g);
  // The step that enters contact ends a bounce slower than 2 g h: P ≤ m ((1 + e) 2 g h + g h).
  BOOST_TEST(last.lambda > 0.0);
  BOOST_TEST(last.lambda <= m * g * (3 + 2 * e) * (1 + 1e-9));
  // Every event's step was observed, with the events first.
  BOOST_TEST(r.observed_after_event >= 1);
  BOOST_TEST(r.times.front() == 0.0);
  BOOST_TEST(r.times.back() == 5.0);
}

// A block of mass m resting on the floor under gravity, lifted by a force a t (a > 0): in contact
// while a t < m g, with λ = m g − a t, and separating at t = m g / a. Moreau–Jean holds u = 0 while
// the step's impulse is positive: P = h (m g − a t_θ) > 0; the separation is reported at the end of
// the first step with P = 0, within one step of the closed form. No impact: it starts at rest.
BOOST_AUTO_TEST_CASE(block_lifted_off_the_floor_separates_at_mg_over_a) {
  const double g = 9.81, m = 1.5, a = 4.0, h = 1e-3;
  const auto sys = particle_on_floor(m, 0.0, [&](double t) { return -m * g + a * t; });
  const Recorded r = run(sys, 0.0, 0.0, 6.0, h);
  BOOST_TEST_REQUIRE(r.events.size() == 2u);
  BOOST_TEST((r.events[0].kind == rc::ContactEventKind::contact));
  BOOST_TEST(r.events[0].t == h);
  BOOST_TEST(std::abs(r.events[0].lambda - (m * g - a * h / 2)) <= 64 * eps * m * g);  // θ = 1/2: f at mid-step
  BOOST_TEST((r.events[1].kind == rc::ContactEventKind::separation));
  // The first step with P = 0 starts past m g / a − h/2 (f at mid-step), and is reported at its end.
  BOOST_TEST(r.events[1].t >= m * g / a + h / 2 - 1e-12);
  BOOST_TEST(r.events[1].t <= m * g / a + 1.5 * h + 1e-12);
  BOOST_TEST(!r.last_active);
  BOOST_TEST(r.last_lambda == 0.0);
}

// A kinematic row u ≥ 0 (Mei §6.7, a ratchet on the velocity) takes no impact: a particle thrown
// down at v0 < 0 is stopped by the row's reaction over the first step (P = m (−v0 + g h), no
// restitution however large e is) and is in contact from then on, with λ = m g.
BOOST_AUTO_TEST_CASE(kinematic_row_takes_no_impact) {
  const double g = 9.81, m = 1.0, h = 1e-3;
  const auto sys = particle_on_floor(m, 0.5, [&](double) { return -m * g; }, rc::GapLevel::velocity);
  const Recorded r = run(sys, 1.0, -3.0, 1.0, h);
  for (const auto& ev : r.events) BOOST_TEST((ev.kind != rc::ContactEventKind::impact));
  BOOST_TEST_REQUIRE(!r.events.empty());
  BOOST_TEST((r.events.front().kind == rc::ContactEventKind::contact));
  BOOST_TEST(r.events.front().t == h);
  BOOST_TEST(std::abs(r.events.front().lambda - m * (3.0 + g * h) / h) <= 64 * eps * m * 3.0 / h);
  BOOST_TEST(r.last_active);
  BOOST_TEST(std::abs(r.last_lambda - m * g) <= 64 * eps * m * g);
}
