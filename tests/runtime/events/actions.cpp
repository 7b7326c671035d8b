// Event actions (events.hpp, integrate_*_events): stop, and edit-the-state with a cooldown, on a
// bouncing ball against its closed form.
//
// The ball: y'' = -g from y(0) = drop_height, y'(0) = 0, the impact law v -> -e v at y = 0. Between impacts
// the motion is a parabola, so the impacts are at
//   t_1 = sqrt(2 drop_height / g),  t_{k+1} = t_k + 2 e^k v_1 / g,  v_1 = sqrt(2 g drop_height),
// with the upward speed e^k v_1 after impact k.
#define BOOST_TEST_MODULE runtime_event_actions
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "eomc/runtime/events.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "eomc/runtime/stepper/rk4.hpp"

namespace rt = eomc::runtime;

namespace {

constexpr double grav = 9.81, restitution = 0.8, drop_height = 1.0;
constexpr int impacts = 5;

struct Ball {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -grav;
  }
};

// g(t, x) = y: the gap to the ground.
struct Gap {
  void operator()(double, const rt::State<double>& x, rt::State<double>& out) const { out[0] = x[0]; }
};

std::vector<double> impact_times(int count) {
  const double v1 = std::sqrt(2.0 * grav * drop_height);
  std::vector<double> t{std::sqrt(2.0 * drop_height / grav)};
  for (int k = 1; k < count; ++k) t.push_back(t.back() + 2.0 * std::pow(restitution, k) * v1 / grav);
  return t;
}

// The bound on |t_k - t_k,exact| for k <= count. Between impacts the solution is a quadratic in t,
// which every method here (order >= 4, dense output of order >= 4, the re-step of rk4) reproduces
// up to round-off, so the integrator's own share is at most its tolerance: a position error of
// rtol |y| + atol becomes a time error of that over the impact speed, at least e^(count-1) v_1.
// Each location adds Brent's bracket, a few ulps of t (events.hpp: eps t, plus 2 eps t in zeroin;
// 8 eps t here). An error dt in t_k shifts the take-off speed by e g dt and the next flight time
// 2 e v / g by 2 e dt: the errors grow at most by (1 + 2 e) per impact.
double time_bound(double rel_tol, double abs_tol, double t_last, int count) {
  const double eps = std::numeric_limits<double>::epsilon();
  const double v_min = std::pow(restitution, count - 1) * std::sqrt(2.0 * grav * drop_height);
  const double per_impact = 8.0 * eps * t_last + (rel_tol * drop_height + abs_tol) / v_min;
  return std::pow(1.0 + 2.0 * restitution, count - 1) * count * per_impact;
}

struct Record {
  std::vector<rt::EventHit<double>> hits;
  std::vector<double> observed_t;
};

// The impact law; `sink` leaves the ball that far below the ground (0: where it was located).
struct Impact {
  double sink = 0.0;
  void operator()(const rt::EventHit<double>&, rt::State<double>& x) const {
    x[1] = -restitution * x[1];
    if (sink > 0.0) x[0] = -sink;
  }
};

rt::EventSpec bounce(double cooldown, rt::EventDirection direction = rt::EventDirection::both) {
  rt::EventSpec spec;
  spec.direction = direction;
  spec.action = rt::EventAction::edit;
  spec.cooldown = cooldown;
  return spec;
}

template <class Run>
Record run_ball(Run&& run, const rt::EventSpec& spec, Impact impact, rt::State<double>& x, double t_end,
                rt::EventOutcome<double>& outcome) {
  Record rec;
  rt::EventLocator<double> locator({spec});
  Gap gap;
  x = {drop_height, 0.0};
  auto observer = [&](double t, const rt::State<double>&) { rec.observed_t.push_back(t); };
  auto on_event = [&](const rt::EventHit<double>& hit) { rec.hits.push_back(hit); };
  outcome = run(x, locator, gap, observer, on_event, impact, t_end);
  return rec;
}

// The three drivers: adaptive Dopri5 and Dop853, fixed-step rk4.
constexpr double rel_tol = 1e-12, abs_tol = 1e-12, step = 1e-3;

template <template <class> class Stepper>
auto adaptive_run() {
  return [](rt::State<double>& x, rt::EventLocator<double>& locator, Gap& gap, auto& observer, auto& on_event, Impact impact,
              double t_end) {
    Stepper<double> stepper;
    Ball ball;
    return rt::integrate_adaptive_events(stepper, ball, x, 0.0, t_end, 0.0, rt::Tolerances{rel_tol, abs_tol}, locator, gap,
                                         observer, on_event, impact);
  };
}

auto fixed_run() {
  return [](rt::State<double>& x, rt::EventLocator<double>& locator, Gap& gap, auto& observer, auto& on_event, Impact impact,
              double t_end) {
    rt::Rk4<double> stepper;
    Ball ball;
    return rt::integrate_fixed_events(stepper, ball, x, 0.0, t_end, step, locator, gap, observer, on_event, impact);
  };
}

// Impacts k = 1..5 at the closed-form times, each once, the state at t_end on the parabola after
// the fifth; the observer sees every impact (the edited state) in time order.
template <class Run>
void check_bounces(Run&& run, const char* name) {
  BOOST_TEST_CONTEXT(name) {
    const std::vector<double> exact = impact_times(impacts + 1);
    const double t_end = 0.5 * (exact[impacts - 1] + exact[impacts]);  // between the 5th and 6th impact
    const double bound = time_bound(rel_tol, abs_tol, t_end, impacts);
    rt::State<double> x;
    rt::EventOutcome<double> outcome;
    // A cooldown shorter than every flight here (the shortest, after impact 5, is 2 e^5 v1 / g).
    const Record rec = run_ball(run, bounce(0.1), Impact{}, x, t_end, outcome);
    BOOST_TEST(!outcome.stopped);
    BOOST_TEST(outcome.edits == static_cast<std::size_t>(impacts));
    BOOST_TEST_REQUIRE(rec.hits.size() == static_cast<std::size_t>(impacts));
    double worst = 0.0;
    for (int k = 0; k < impacts; ++k) worst = std::max(worst, std::abs(rec.hits[k].t - exact[k]));
    BOOST_TEST_MESSAGE(name << ": largest impact-time error " << worst << ", bound " << bound);
    for (int k = 0; k < impacts; ++k) {
      BOOST_TEST_CONTEXT("impact " << k + 1) {
        BOOST_TEST(std::abs(rec.hits[k].t - exact[k]) <= bound);
        BOOST_TEST(rec.hits[k].direction == -1);
        BOOST_TEST((rec.hits[k].action == rt::EventAction::edit));
        // The hit carries the state before the edit: on the ground, falling at the impact speed.
        const double v_in = std::pow(restitution, k) * std::sqrt(2.0 * grav * drop_height);
        BOOST_TEST(std::abs(rec.hits[k].x[1] + v_in) <= grav * bound + rel_tol * v_in + abs_tol);
      }
    }
    for (std::size_t i = 1; i < rec.observed_t.size(); ++i) BOOST_TEST(rec.observed_t[i] >= rec.observed_t[i - 1]);
    const double v5 = std::pow(restitution, impacts) * std::sqrt(2.0 * grav * drop_height), tau = t_end - exact[impacts - 1];
    const double dy = (v5 + grav * tau) * bound;  // a time error moves the state at most at its speed
    BOOST_TEST(std::abs(x[0] - (v5 * tau - 0.5 * grav * tau * tau)) <= dy + rel_tol * drop_height + abs_tol);
    BOOST_TEST(std::abs(x[1] - (v5 - grav * tau)) <= grav * bound + rel_tol * v5 + abs_tol);
  }
}

// An impact that leaves the ball a hair below the ground (as a located root may, by an ulp):
// without a cooldown the gap crosses zero upwards at once and the impact law fires again at the
// same time, sending the ball down through the floor; with one, it is the next true impact.
template <class Run>
void check_cooldown(Run&& run, const char* name) {
  BOOST_TEST_CONTEXT(name) {
    const std::vector<double> exact = impact_times(3);
    const double t_end = 0.5 * (exact[1] + exact[2]);
    const double sink = 1e-9 * drop_height, v_up = restitution * std::sqrt(2.0 * grav * drop_height);
    rt::State<double> x;
    rt::EventOutcome<double> outcome;
    const Record refire = run_ball(run, bounce(0.0), Impact{sink}, x, t_end, outcome);
    BOOST_TEST_REQUIRE(refire.hits.size() >= 2u);
    BOOST_TEST(refire.hits[1].direction == 1);
    // It re-fires where the ball has climbed back the sink at the take-off speed: far within a flight.
    BOOST_TEST(refire.hits[1].t - refire.hits[0].t <= 2.0 * sink / v_up);

    const Record cooled = run_ball(run, bounce(0.1), Impact{sink}, x, t_end, outcome);
    BOOST_TEST_REQUIRE(cooled.hits.size() == 2u);
    BOOST_TEST(cooled.hits[1].direction == -1);
    // The sink delays the second impact by sink / v_up.
    BOOST_TEST(std::abs(cooled.hits[1].t - exact[1]) <= sink / v_up + time_bound(rel_tol, abs_tol, t_end, 2));
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(bouncing_ball_impact_times_with_every_driver) {
  check_bounces(adaptive_run<rt::Dopri5>(), "dopri5");
  check_bounces(adaptive_run<rt::Dop853>(), "dop853");
  check_bounces(fixed_run(), "rk4");
}

BOOST_AUTO_TEST_CASE(the_cooldown_prevents_a_refire_at_the_same_time) {
  check_cooldown(adaptive_run<rt::Dopri5>(), "dopri5");
  check_cooldown(fixed_run(), "rk4");
}

// An edit that puts the ball back a hair above the ground, still falling, with no cooldown: the gap
// crosses zero again within 1e-300 / v of the edit, the same time to the last bit, and the edit
// would repeat there without end. The drivers refuse it at the second edit with the event's index
// and time, instead of spinning until the step budget runs out.
BOOST_AUTO_TEST_CASE(an_edit_that_refires_at_once_is_an_error) {
  const double t1 = impact_times(1)[0];
  struct Hover {
    void operator()(const rt::EventHit<double>&, rt::State<double>& x) const { x[0] = 1e-300; }
  };
  const auto run = [&](auto&& integrate) {
    rt::EventLocator<double> locator({bounce(0.0, rt::EventDirection::down)});
    rt::State<double> x{drop_height, 0.0};
    try {
      integrate(locator, x);
    } catch (const rt::IntegrationError& e) {
      BOOST_TEST((e.kind() == rt::IntegrationError::Kind::event_loop));
      BOOST_TEST(std::abs(e.t() - t1) <= time_bound(rel_tol, abs_tol, t1, 1));
      BOOST_TEST(std::string(e.what()).find("event 0 fired again") != std::string::npos);
      return true;
    }
    return false;
  };
  Ball ball;
  Gap gap;
  auto obs = [](double, const rt::State<double>&) {};
  auto on_event = [](const rt::EventHit<double>&) {};
  BOOST_TEST(run([&](rt::EventLocator<double>& locator, rt::State<double>& x) {
    rt::Dopri5<double> stepper;
    rt::integrate_adaptive_events(stepper, ball, x, 0.0, 2.0, 0.0, rt::Tolerances{rel_tol, abs_tol}, locator, gap, obs,
                                  on_event, Hover{});
  }));
  BOOST_TEST(run([&](rt::EventLocator<double>& locator, rt::State<double>& x) {
    rt::Rk4<double> stepper;
    rt::integrate_fixed_events(stepper, ball, x, 0.0, 2.0, step, locator, gap, obs, on_event, Hover{});
  }));
}

// EventAction::stop is the terminal event; an edit without an edit callback is refused.
BOOST_AUTO_TEST_CASE(stop_action_and_edit_without_callback) {
  const double t1 = impact_times(1)[0];
  Ball ball;
  Gap gap;
  rt::Dopri5<double> stepper;
  rt::State<double> x{drop_height, 0.0};
  rt::EventSpec stop;
  stop.direction = rt::EventDirection::down;
  stop.action = rt::EventAction::stop;
  rt::EventLocator<double> stopping({stop});
  auto obs = [](double, const rt::State<double>&) {};
  auto on_event = [](const rt::EventHit<double>&) {};
  const auto out = rt::integrate_adaptive_events(stepper, ball, x, 0.0, 2.0, 0.0, rt::Tolerances{rel_tol, abs_tol}, stopping,
                                                 gap, obs, on_event);
  BOOST_TEST(out.stopped);
  BOOST_TEST(std::abs(out.t - t1) <= time_bound(rel_tol, abs_tol, t1, 1));
  BOOST_TEST(std::abs(x[0]) <= rel_tol * drop_height + abs_tol);

  rt::EventLocator<double> editing({bounce(0.1)});
  x = {drop_height, 0.0};
  BOOST_CHECK_THROW(rt::integrate_adaptive_events(stepper, ball, x, 0.0, 2.0, 0.0, rt::Tolerances{rel_tol, abs_tol}, editing,
                                                  gap, obs, on_event),
                    std::invalid_argument);
  BOOST_CHECK_THROW(rt::EventLocator<double>({bounce(-1.0)}), std::invalid_argument);
}
