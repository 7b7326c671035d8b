// Crossings that open and close inside one step (events.hpp's resolution of g over every step). In
// free flight the state is a quadratic in t, which dopri5 and dop853 reproduce with no error
// estimate to speak of, so their steps grow to the whole flight: a ball thrown at a ceiling it just
// reaches, or resting on nothing above a table that vibrates faster than any step, has the same
// sign of its gap at both ends of a step. Closed forms: the ceiling's impact time and the state
// after it (Newton's law, Mei, Special Topics in Analytical Mechanics, §6.5), the table's first
// contact as the first root of a known function of t, and the crossings of a scene event.
#define BOOST_TEST_MODULE runtime_contact_never_miss
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
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

namespace {

// y'' = −g over the floor y ≥ 0 (gap y, or any function of y given), from (y0, 0).
ct::ContactSystem<double> over_floor(double e, double (*gap)(double), double (*slope)(double)) {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{e, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = 1.0; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f[0] = -grav; };
  sys.gaps = [gap](double, const Vec& q, const Vec&, Vec& g) { g[0] = gap(q[0]); };
  sys.rows = [slope](double, const Vec& q, const Vec& u, Mat& W, Vec& b) {
    // g̈ = g'(y) ÿ + g''(y) ẏ²; only the straight floor and y³ are used here.
    W(0, 0) = slope(q[0]);
    b[0] = slope(1.0) == 1.0 ? 0.0 : 6.0 * q[0] * u[0] * u[0];
  };
  return sys;
}
double straight(double y) { return y; }
double unit(double) { return 1.0; }
double cubed(double y) { return y * y * y; }
double cubed_slope(double y) { return 3.0 * y * y; }

template <class F>
void expect_contact_error(F&& run, std::size_t contact, const char* words) {
  try {
    run();
    BOOST_ERROR("expected an IntegrationError of Kind::contact");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST_MESSAGE(e.what());
    BOOST_TEST((e.kind() == rt::IntegrationError::Kind::contact));
    BOOST_TEST(e.component() == contact);
    BOOST_TEST(std::string(e.what()).find(words) != std::string::npos);
  }
}

const auto quiet = [](double, const rt::State<double>&, const Vec&, const std::vector<bool>&) {};

}  // namespace

BOOST_AUTO_TEST_CASE(every_resolvable_impact_is_integrated_before_zeno) {
  // Dropped from 1 m with e = 0.8: t_k = t1 (1 + 2 Σ_{j<k} e^j), t1 = √(2/g), Zeno at
  // t1 (1 + e)/(1 − e). The 10th impact (5 were made before the series took over) at its time, and
  // the CSV's view: the observer sees the state after each impact at that impact's time.
  const rt::Tolerances tol{1e-10, 1e-12};
  constexpr double e = 0.8;
  const double t1 = std::sqrt(2.0 / grav);
  const auto t_k = [&](int k) { return t1 * (1.0 + 2.0 * e * (1.0 - std::pow(e, k - 1)) / (1.0 - e)); };
  rt::Dopri5<double> stepper;
  rt::State<double> x{1.0, 0.0};
  std::vector<double> seen;
  ct::EventDrivenOptions<double> options;
  std::vector<ct::ContactEvent<double>> reported;
  options.on_event = [&](const ct::ContactEvent<double>& ev) { reported.push_back(ev); };
  const auto out = ct::integrate_event_driven(
      stepper, over_floor(e, straight, unit), x, 0.0, 20.0, tol,
      [&](double t, const rt::State<double>&, const Vec&, const std::vector<bool>&) {
        if (!reported.empty() && reported.back().t == t) seen.push_back(t);
      },
      options);
  const auto hits = impacts(out);
  BOOST_TEST_MESSAGE(hits.size() << " impacts before Zeno");
  BOOST_REQUIRE(hits.size() >= 10u);
  for (int k = 1; k <= int(hits.size()); ++k) {
    // Each impact time carries the tolerance over the impact speed e^(k−1) √(2g) and Brent's
    // bracket; an error dt moves the next flight by 2 e dt.
    double bound = 0.0;
    for (int j = 1; j <= k; ++j)
      bound = bound * (1.0 + 2.0 * e) + 8.0 * eps * t_k(j) + (tol.rtol + tol.atol) / (std::pow(e, j - 1) * std::sqrt(2.0 * grav));
    BOOST_TEST(std::abs(hits[std::size_t(k - 1)].t - t_k(k)) <= bound, "impact " << k);
  }
  // The series took over only below 100 impact-time errors: the last interval is that short.
  const double last = hits.back().t - hits[hits.size() - 2].t;
  const double speed = std::pow(e, int(hits.size()) - 1) * std::sqrt(2.0 * grav);
  BOOST_TEST(last <= 100.0 * (8.0 * eps * hits.back().t + (tol.rtol * 2.0 + tol.atol) / speed) * 1.01);
  // Every impact was shown at its own time, the Zeno point once.
  for (const auto& h : hits) BOOST_TEST(std::count(seen.begin(), seen.end(), h.t) >= 1);
  BOOST_REQUIRE(!out.events.empty());
  BOOST_TEST((out.events.back().kind == ct::ContactEventKind::contact ||
              out.events.back().kind == ct::ContactEventKind::zeno));
}

BOOST_AUTO_TEST_CASE(a_gap_without_gradient_on_its_boundary_is_refused_where_it_closes) {
  // y³ ≥ 0 is the set y ≥ 0 with ∇g = 0 on g = 0: the ball arrives at 4.43 m/s and no finite
  // impulse stops it. An error at the contact and the time, not λ = 10⁴⁷.
  expect_contact_error(
      [] {
        rt::Dopri5<double> stepper;
        rt::State<double> x{1.0, 0.0};
        ct::integrate_event_driven(stepper, over_floor(0.5, cubed, cubed_slope), x, 0.0, 2.0,
                                   rt::Tolerances{1e-10, 1e-12}, quiet);
      },
      0, "gradient of the constraint vanishes");
}

namespace {
// A particle on a line between two walls at the same place, x ≥ 0 and −x ≥ 0, arriving at x = 0
// with speed −1.
ct::ContactSystem<double> pinched(double e) {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{e, ct::GapLevel::position}, {e, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = 1.0; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f[0] = 0.0; };
  sys.gaps = [](double, const Vec& q, const Vec&, Vec& g) {
    g[0] = q[0];
    g[1] = -q[0];
  };
  sys.rows = [](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    W(1, 0) = -1.0;
    b.setZero();
  };
  return sys;
}
}  // namespace

BOOST_AUTO_TEST_CASE(walls_that_pinch_are_refused_or_stop_the_particle) {
  // e = 1: the wall x ≥ 0 must send the particle back into −x ≥ 0; no impulse keeps both
  // (Newton's law on the first, ġ⁺ ≥ 0 on the second): refused, not x = −1 at the end.
  expect_contact_error(
      [] {
        rt::Dopri5<double> stepper;
        rt::State<double> x{0.0, -1.0};
        ct::integrate_event_driven(stepper, pinched(1.0), x, 0.0, 1.0, rt::Tolerances{1e-10, 1e-12}, quiet);
      },
      0, "no impulse satisfies Newton's law");
  // e = 0: the impact stops it at x = 0, where it stays.
  rt::Dopri5<double> stepper;
  rt::State<double> x{0.0, -1.0};
  ct::integrate_event_driven(stepper, pinched(0.0), x, 0.0, 1.0, rt::Tolerances{1e-10, 1e-12}, quiet);
  BOOST_TEST(std::abs(x[0]) <= 1e-12);
  BOOST_TEST(std::abs(x[1]) <= 1e-12);
}

BOOST_AUTO_TEST_CASE(an_elastic_ball_bounces_past_a_hundred_thousand_impacts) {
  // e = 1 from 1 m: impacts at t1 (2k − 1), for ever; the intervals do not shrink, so nothing is
  // refused (the old cap of 10⁵ impacts called this an undetected Zeno run). The energy stays g to
  // the integrator's tolerance times the flights (dopri5 on a quadratic: round-off per step).
  const double t1 = std::sqrt(2.0 / grav), t_end = t1 * (2.0 * 100200 - 1.0) + t1 / 2.0;
  rt::Dopri5<double> stepper;
  rt::State<double> x{1.0, 0.0};
  const auto out = ct::integrate_event_driven(stepper, over_floor(1.0, straight, unit), x, 0.0, t_end,
                                              rt::Tolerances{1e-10, 1e-12}, quiet);
  const auto hits = impacts(out);
  BOOST_TEST(hits.size() == 100200u);
  const double energy = 0.5 * x[1] * x[1] + grav * x[0];
  BOOST_TEST_MESSAGE("energy after " << hits.size() << " impacts: " << energy << " (error " << energy - grav << ")");
  BOOST_TEST(std::abs(energy - grav) <= 1e-9 * grav);
  BOOST_TEST(std::abs(hits.back().t - t1 * (2.0 * 100200 - 1.0)) <= 1e-9 * t_end);
}

BOOST_AUTO_TEST_CASE(impacts_that_accumulate_unresolved_are_refused_with_the_time) {
  // e = 0.8 with the Zeno extrapolation off: the intervals fall below the impact times' own error
  // and keep falling; refused at the contact, at a time within that error of t∞.
  const double t1 = std::sqrt(2.0 / grav), t_inf = t1 * 1.8 / 0.2;
  ct::EventDrivenOptions<double> options;
  options.detect_zeno = false;
  try {
    rt::Dopri5<double> stepper;
    rt::State<double> x{1.0, 0.0};
    ct::integrate_event_driven(stepper, over_floor(0.8, straight, unit), x, 0.0, 20.0, rt::Tolerances{1e-10, 1e-12},
                               quiet, options);
    BOOST_ERROR("expected a refusal");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST_MESSAGE(e.what());
    BOOST_TEST((e.kind() == rt::IntegrationError::Kind::contact));
    BOOST_TEST(std::string(e.what()).find("cannot resolve") != std::string::npos);
    BOOST_TEST(std::abs(e.t() - t_inf) <= 1e-6);
  }
}
