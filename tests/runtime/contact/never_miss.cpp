// Crossings that open and close inside one step (events.hpp's resolution of g over every step). In
// free flight the state is a quadratic in t, which dopri5 and dop853 reproduce with no error
// estimate to speak of, so their steps grow to the whole flight: a ball thrown at a ceiling it just
// reaches, or resting on nothing above a table that vibrates faster than any step, has the same
// sign of its gap at both ends of a step. Closed forms: the ceiling's impact time and the state
// after it (Newton's law, Mei, Special Topics in Analytical Mechanics, §6.5), the table's first
// contact as the first root of a known function of t, and the crossings of a scene event.
#define BOOST_TEST_MODULE runtime_contact_never_miss
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/contact/event_driven.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"

namespace rt = eomc::runtime;
namespace ct = eomc::runtime::contact;
using Vec = ct::Vector<double>;
using Mat = ct::Matrix<double>;

namespace {

constexpr double grav = 9.81;
const double eps = std::numeric_limits<double>::epsilon();

std::vector<ct::ContactEvent<double>> impacts(const ct::EventDrivenOutcome<double>& out) {
  std::vector<ct::ContactEvent<double>> v;
  for (const auto& e : out.events)
    if (e.kind == ct::ContactEventKind::impact) v.push_back(e);
  return v;
}

// y'' = −g under the ceiling y ≤ 10 (gap 10 − y, W = −1), e = 1/2, thrown up at v0 from y = 0.
constexpr double ceiling = 10.0, e_ceiling = 0.5, v0 = 14.013850256086064;

ct::ContactSystem<double> under_ceiling() {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{e_ceiling, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = 1.0; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f[0] = -grav; };
  sys.gaps = [](double, const Vec& q, const Vec&, Vec& g) { g[0] = ceiling - q[0]; };
  sys.rows = [](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = -1.0;
    b[0] = 0.0;
  };
  return sys;
}

template <template <class> class Stepper>
void ceiling_case(const rt::Tolerances& tol) {
  // Impact when 10 = v0 t − g t²/2 first holds; the speed there v⁻ = √(v0² − 20 g) (0.434 m/s: the
  // free parabola would spend 0.088 s above the ceiling, a seventh of one free-flight step); then
  // ẏ = −e v⁻ and free flight down from y = 10.
  const double v_minus = std::sqrt(v0 * v0 - 2.0 * grav * ceiling), t_hit = (v0 - v_minus) / grav;
  const double t_end = 3.0, s = t_end - t_hit;
  const double y_end = ceiling - e_ceiling * v_minus * s - 0.5 * grav * s * s;
  Stepper<double> stepper;
  rt::State<double> x{0.0, v0};
  const auto out = ct::integrate_event_driven(stepper, under_ceiling(), x, 0.0, t_end, tol,
                                              [](double, const rt::State<double>&, const Vec&,
                                                 const std::vector<bool>&) {});
  const auto hits = impacts(out);
  BOOST_REQUIRE_EQUAL(hits.size(), 1u);
  // The impact time carries the state's tolerance at the ceiling over the impact speed and Brent's
  // bracket; an error dt there moves y(t_end) by (1 + e) g dt (t_end − t_hit) (the post-impact speed
  // is off by (1 + e) g dt), plus the tolerance of the free flight's few steps.
  const double dt = 8.0 * eps * t_hit + (tol.rtol * ceiling + tol.atol) / v_minus;
  const double dy = (1.0 + e_ceiling) * grav * dt * s + 8.0 * (tol.rtol * std::abs(y_end) + tol.atol);
  BOOST_TEST_MESSAGE("order " << Stepper<double>::order << ", rtol " << tol.rtol << ": impact at " << hits[0].t << " (error "
                                            << hits[0].t - t_hit << "), y(3) = " << x[0] << " (error "
                                            << x[0] - y_end << ", bound " << dy << "), " << out.stats.accepted
                                            << " steps");
  BOOST_TEST(std::abs(hits[0].t - t_hit) <= dt);
  BOOST_TEST(hits[0].rate_after == -e_ceiling * hits[0].rate_before, boost::test_tools::tolerance(8 * eps));
  BOOST_TEST(std::abs(x[0] - y_end) <= dy);
}

// A ball at rest at y = 1 over a table at 0.9 sin(1000 t): gap y − 0.9 sin(1000 t), w = −900 cos,
// b = 9·10⁵ sin (∂²g/∂t²).
constexpr double amplitude = 0.9, omega = 1000.0;

ct::ContactSystem<double> over_vibrating_table() {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{0.5, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = 1.0; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f[0] = -grav; };
  sys.gaps = [](double t, const Vec& q, const Vec&, Vec& g) { g[0] = q[0] - amplitude * std::sin(omega * t); };
  sys.rows = [](double t, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    b[0] = amplitude * omega * omega * std::sin(omega * t);
  };
  sys.time_rates = [](double t, const Vec&, Vec& w) { w[0] = -amplitude * omega * std::cos(omega * t); };
  return sys;
}

// The first root of 1 − g t²/2 − 0.9 sin(1000 t), found independently: a scan at a thousandth of the
// table's period, then bisection to the last bit.
double first_table_contact() {
  const auto gap = [](double t) { return 1.0 - 0.5 * grav * t * t - amplitude * std::sin(omega * t); };
  const double dt = 2.0 * std::acos(-1.0) / omega / 1000.0;
  double a = 0.0;
  while (gap(a + dt) > 0.0) a += dt;
  double b = a + dt;
  for (int k = 0; k < 200 && b - a > 0.0; ++k) {
    const double m = 0.5 * (a + b);
    if (m == a || m == b) break;
    (gap(m) > 0.0 ? a : b) = m;
  }
  return a;
}

}  // namespace

BOOST_AUTO_TEST_CASE(ceiling_reached_inside_one_free_flight_step) {
  ceiling_case<rt::Dopri5>({1e-10, 1e-12});
  ceiling_case<rt::Dopri5>({1e-14, 1e-14});
  ceiling_case<rt::Dop853>({1e-10, 1e-12});
  ceiling_case<rt::Dop853>({1e-14, 1e-14});
}

BOOST_AUTO_TEST_CASE(vibrating_table_meets_the_ball_where_the_closed_form_says) {
  const rt::Tolerances tol{1e-10, 1e-12};
  rt::Dopri5<double> stepper;
  rt::State<double> x{1.0, 0.0};
  const auto out = ct::integrate_event_driven(stepper, over_vibrating_table(), x, 0.0, 0.2, tol,
                                              [](double, const rt::State<double>&, const Vec&,
                                                 const std::vector<bool>&) {});
  const auto hits = impacts(out);
  BOOST_REQUIRE(!hits.empty());
  const double t_star = first_table_contact();
  // The gap's rate at contact (|ġ⁻| about 90 m/s: the table rises at up to 900 m/s) turns the
  // locator's bracket and the state's tolerance into a time error.
  const double rate = std::abs(hits[0].rate_before);
  const double dt = 8.0 * eps * t_star + (tol.rtol + tol.atol) / rate;
  BOOST_TEST_MESSAGE("first contact at " << hits[0].t << ", closed form " << t_star << ", rate " << rate);
  BOOST_TEST(std::abs(hits[0].t - t_star) <= dt);
}

BOOST_AUTO_TEST_CASE(a_scene_event_crossed_twice_inside_one_step_is_seen_twice) {
  // y'' = −g from y = 0 at v0: h = y − 10 goes up through zero and down again 0.088 s later, inside
  // one free-flight step. Both crossings, at (v0 ∓ √(v0² − 20 g)) / g.
  const rt::Tolerances tol{1e-10, 1e-12};
  auto sys = [](double, const rt::State<double>& x, rt::State<double>& dx) {
    dx[0] = x[1];
    dx[1] = -grav;
  };
  auto h = [](double, const rt::State<double>& x, rt::State<double>& out) { out[0] = x[0] - ceiling; };
  rt::EventLocator<double> locator({rt::EventSpec{}});
  std::vector<rt::EventHit<double>> hits;
  rt::Dopri5<double> stepper;
  rt::State<double> x{0.0, v0};
  const auto out = rt::integrate_adaptive_events(stepper, sys, x, 0.0, 3.0, 0.0, tol, locator, h,
                                                 [](double, const rt::State<double>&) {},
                                                 [&](const rt::EventHit<double>& hit) { hits.push_back(hit); });
  const double root = std::sqrt(v0 * v0 - 2.0 * grav * ceiling);
  BOOST_TEST_MESSAGE(out.stats.accepted << " steps, " << locator.evaluations() << " evaluations of h");
  BOOST_REQUIRE_EQUAL(hits.size(), 2u);
  const double dt = 8.0 * eps * 3.0 + (tol.rtol * ceiling + tol.atol) / root;
  BOOST_TEST(hits[0].direction == 1);
  BOOST_TEST(hits[1].direction == -1);
  BOOST_TEST(std::abs(hits[0].t - (v0 - root) / grav) <= dt);
  BOOST_TEST(std::abs(hits[1].t - (v0 + root) / grav) <= dt);
  BOOST_TEST(locator.unresolved() == 0u);
}

BOOST_AUTO_TEST_CASE(a_narrow_smooth_dip_inside_one_step_is_crossed_twice) {
  // h = 1 − (3/2) exp(−((t − 1/2)/σ)²), σ = 1/20, on ẋ = 1 (one step covers [0, 1]): below zero
  // for |t − 1/2| < σ √ln(3/2), a tenth of the step. Both crossings.
  const rt::Tolerances tol{1e-10, 1e-12};
  constexpr double sigma = 0.05;
  auto sys = [](double, const rt::State<double>&, rt::State<double>& dx) { dx[0] = 1.0; };
  auto h = [](double t, const rt::State<double>&, rt::State<double>& out) {
    const double z = (t - 0.5) / sigma;
    out[0] = 1.0 - 1.5 * std::exp(-z * z);
  };
  rt::EventLocator<double> locator({rt::EventSpec{}});
  std::vector<rt::EventHit<double>> hits;
  rt::Dopri5<double> stepper;
  rt::State<double> x{0.0};
  const auto out = rt::integrate_adaptive_events(stepper, sys, x, 0.0, 1.0, 0.0, tol, locator, h,
                                                 [](double, const rt::State<double>&) {},
                                                 [&](const rt::EventHit<double>& hit) { hits.push_back(hit); });
  BOOST_TEST_MESSAGE(out.stats.accepted << " steps, " << locator.evaluations() << " evaluations of h");
  BOOST_REQUIRE_EQUAL(hits.size(), 2u);
  const double half_width = sigma * std::sqrt(std::log(1.5));
  // h' = 3 z exp(−z²)/σ at the crossings: Brent's bracket of 8 ε t in t.
  BOOST_TEST(std::abs(hits[0].t - (0.5 - half_width)) <= 8 * eps);
  BOOST_TEST(std::abs(hits[1].t - (0.5 + half_width)) <= 8 * eps);
  BOOST_TEST(locator.unresolved() == 0u);
}

BOOST_AUTO_TEST_CASE(a_jump_near_zero_is_reported_as_unresolved) {
  // h = 1 before t = 1/2 and 10⁻¹³ + (t − 1/2) after: no cubic fits across the jump at any length,
  // and beside it h is too near zero to excuse the misfit, so the piece holding the jump shrinks to
  // the ulps of t and is reported there; no crossing is invented.
  const rt::Tolerances tol{1e-10, 1e-12};
  auto sys = [](double, const rt::State<double>&, rt::State<double>& dx) { dx[0] = 1.0; };
  auto h = [](double t, const rt::State<double>&, rt::State<double>& out) {
    out[0] = t < 0.5 ? 1.0 : 1e-13 + (t - 0.5);
  };
  rt::EventLocator<double> locator({rt::EventSpec{}});
  std::vector<rt::EventHit<double>> hits;
  rt::Dopri5<double> stepper;
  rt::State<double> x{0.0};
  rt::integrate_adaptive_events(stepper, sys, x, 0.0, 1.0, 0.0, tol, locator, h,
                                [](double, const rt::State<double>&) {},
                                [&](const rt::EventHit<double>& hit) { hits.push_back(hit); });
  BOOST_TEST(hits.empty());
  BOOST_TEST(locator.unresolved() > 0u);
  BOOST_TEST(std::abs(locator.first_unresolved() - 0.5) <= 1e-12);
}
