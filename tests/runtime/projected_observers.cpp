// What the observers and the events see of a Projecting system (integrate.hpp): the state the
// integration goes on from. Uniform rotation ẋ = −y, ẏ = x kept on the unit circle by project(),
// integrated at a loose tolerance so that an unprojected step end sits 1e-7 off the circle: every
// observed state, every event state and every dense-output time lies on it to round-off (a few
// ulps of x² + y² = 1).
#define BOOST_TEST_MODULE runtime_projected_observers
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/stepper/rk4.hpp"

namespace rt = eomc::runtime;

namespace {

const double eps = std::numeric_limits<double>::epsilon();
const double bound = 8 * eps;  // x² + y² − 1 after x /= r, y /= r: a few roundings

struct Circle {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dx) const {
    dx[0] = -x[1];
    dx[1] = x[0];
  }
  void project(double, rt::State<double>& x) const {
    const double r = std::hypot(x[0], x[1]);
    x[0] /= r;
    x[1] /= r;
  }
};
static_assert(rt::Projecting<Circle, double>);

double off(const rt::State<double>& x) { return std::abs(x[0] * x[0] + x[1] * x[1] - 1.0); }

}  // namespace

BOOST_AUTO_TEST_CASE(adaptive_observers_and_events_see_the_projected_state) {
  Circle sys;
  rt::Dopri5<double> stepper;
  rt::State<double> x{1.0, 0.0};
  double worst = 0.0, worst_event = 0.0;
  std::size_t events = 0;
  rt::EventLocator<double> locator({rt::EventSpec{}});
  auto g = [](double, const rt::State<double>& xs, rt::State<double>& out) { out[0] = xs[1]; };
  rt::integrate_adaptive_events(
      stepper, sys, x, 0.0, 20.0, 0.0, rt::Tolerances{1e-6, 1e-6}, locator, g,
      [&](double, const rt::State<double>& xs) { worst = std::max(worst, off(xs)); },
      [&](const rt::EventHit<double>& hit) {
        ++events;
        worst_event = std::max(worst_event, off(hit.x));
      });
  BOOST_TEST_MESSAGE("observed " << worst << ", events " << worst_event);
  BOOST_TEST(events == 6u);  // y = 0 at kπ, k = 1..6 (6π < 20 < 7π)
  BOOST_TEST(worst <= bound);
  BOOST_TEST(worst_event <= bound);
}

BOOST_AUTO_TEST_CASE(dense_output_times_are_projected_too) {
  Circle sys;
  rt::Dopri5<double> stepper;
  rt::State<double> x{1.0, 0.0};
  std::vector<double> times;
  for (int k = 0; k <= 200; ++k) times.push_back(0.1 * k);
  double worst = 0.0;
  rt::integrate_times(stepper, sys, x, times, 0.0, rt::Tolerances{1e-6, 1e-6},
                      [&](double, const rt::State<double>& xs) { worst = std::max(worst, off(xs)); });
  BOOST_TEST(worst <= bound);
}

BOOST_AUTO_TEST_CASE(fixed_step_observers_see_the_projected_state) {
  Circle sys;
  rt::Rk4<double> stepper;
  rt::State<double> x{1.0, 0.0};
  double worst = 0.0;
  rt::integrate_fixed(stepper, sys, x, 0.0, 20.0, 0.05,
                      [&](double, const rt::State<double>& xs) { worst = std::max(worst, off(xs)); });
  BOOST_TEST(worst <= bound);
}

// An edit at an event (an impact law, a manoeuvre) may leave the manifold: here it stretches the
// state by 1.5 where y crosses zero upwards (t = 2π, 4π, 6π before 20). The integration restarts
// from the projected edit, and so the observer's row at t_e shows that state, not the stretched one
// (0.5 · 2.5 = 1.25 off). Adaptive and fixed-step drivers alike.
BOOST_AUTO_TEST_CASE(edited_states_are_projected_before_the_observer_sees_them) {
  rt::EventSpec spec;
  spec.direction = rt::EventDirection::up;
  spec.action = rt::EventAction::edit;
  spec.cooldown = 0.5;  // y stays at zero after the stretch: no second crossing read there
  auto g = [](double, const rt::State<double>& xs, rt::State<double>& out) { out[0] = xs[1]; };
  auto stretch = [](const rt::EventHit<double>&, rt::State<double>& xs) {
    xs[0] *= 1.5;
    xs[1] *= 1.5;
  };
  for (const bool fixed : {false, true}) {
    Circle sys;
    rt::State<double> x{1.0, 0.0};
    double worst = 0.0;
    auto observe = [&](double, const rt::State<double>& xs) { worst = std::max(worst, off(xs)); };
    rt::EventLocator<double> locator({spec});
    rt::EventOutcome<double> out;
    if (fixed) {
      rt::Rk4<double> stepper;
      out = rt::integrate_fixed_events(stepper, sys, x, 0.0, 20.0, 0.05, locator, g, observe,
                                       [](const rt::EventHit<double>&) {}, stretch);
    } else {
      rt::Dopri5<double> stepper;
      out = rt::integrate_adaptive_events(stepper, sys, x, 0.0, 20.0, 0.0, rt::Tolerances{1e-6, 1e-6}, locator, g,
                                          observe, [](const rt::EventHit<double>&) {}, stretch);
    }
    BOOST_TEST_MESSAGE((fixed ? "rk4" : "dopri5") << ": " << out.edits << " edits, observed off the circle by " << worst);
    BOOST_TEST(out.edits == 3u);
    BOOST_TEST(worst <= bound);
    BOOST_TEST(off(x) <= bound);
  }
}
