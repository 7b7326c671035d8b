// Event location (events.hpp, integrate_*_events) against closed forms, and compensated summation
// of the explicit Runge-Kutta methods (rk4, dopri5, dop853).
#define BOOST_TEST_MODULE runtime_events
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "eomc/runtime/runtime.hpp"
#include "../../support/pendulum.hpp"

namespace rt = eomc::runtime;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double pi = 3.141592653589793238462643383279502884;

// A projectile y'' = -g, x = (y, v): y = v0 t - g t^2 / 2. Apex (v = 0) at v0/g, ground (y = 0,
// downwards) at 2 v0/g.
constexpr double g_acc = 9.81, v0 = 7.0;
struct ProjectileRhs {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -g_acc;
  }
};
struct ProjectileAcc {
  void operator()(double, const rt::State<double>&, rt::State<double>& a) const { a[0] = -g_acc; }
};
// g_0 = v (apex), g_1 = y (ground).
struct ProjectileEvents {
  void operator()(double, const rt::State<double>& x, rt::State<double>& out) const {
    out[0] = x[1];
    out[1] = x[0];
  }
};

// Bound on the located time of a crossing of g = x[k], derived: the solution is a polynomial of
// degree 2 and every method here (order >= 2, their dense outputs and re-steps) reproduces it in
// exact arithmetic, so the state is off by round-off alone: each of the N steps (and the final
// evaluation at the root) rounds every component by at most a few eps times max|x|, so
// |dg| <= (N + 4) * 4 eps * X. The crossing moves by |dg| / |g'|, plus Brent's bracket of
// 4 eps |t|. For ~200 steps this is ~1e-13 relative; a wrong location (a step end, a linear
// interpolation of a quadratic) is off by ~1e-3.
double projectile_bound(std::size_t steps, double slope, double t) {
  const double X = v0 * v0 / (2 * g_acc) + v0;  // max |y| + max |v| over the flight
  return (double(steps) + 4) * 4 * eps * X / slope + 4 * eps * t;
}

struct Recorder {
  std::vector<rt::EventHit<double>> hits;
  void operator()(const rt::EventHit<double>& h) { hits.push_back(h); }
};

std::vector<rt::EventSpec> projectile_specs(bool ground_terminal) {
  return {{rt::EventDirection::down, false}, {rt::EventDirection::down, ground_terminal}};
}

template <class Run>
void check_projectile(const std::string& method, Run&& run) {
  rt::State<double> x{0.0, v0};
  rt::EventLocator<double> locator(projectile_specs(true));
  Recorder rec;
  const rt::EventOutcome<double> out = run(x, locator, rec);
  const double t_apex = v0 / g_acc, t_ground = 2 * v0 / g_acc;
  BOOST_TEST_CONTEXT(method) {
    BOOST_REQUIRE_EQUAL(rec.hits.size(), 2u);
    BOOST_TEST(rec.hits[0].index == 0u);
    BOOST_TEST(rec.hits[0].direction == -1);
    BOOST_TEST(std::abs(rec.hits[0].t - t_apex) <= projectile_bound(out.stats.accepted, g_acc, t_apex),
               "apex " << rec.hits[0].t << " vs " << t_apex << ", relative " << std::abs(rec.hits[0].t / t_apex - 1));
    BOOST_TEST(rec.hits[1].index == 1u);
    BOOST_TEST(rec.hits[1].terminal);
    BOOST_TEST(std::abs(rec.hits[1].t - t_ground) <= projectile_bound(out.stats.accepted, v0, t_ground),
               "ground " << rec.hits[1].t << " vs " << t_ground << ", relative "
                         << std::abs(rec.hits[1].t / t_ground - 1));
    // Stopped at the ground with the state there: y = 0 to round-off, v = -v0.
    BOOST_TEST(out.stopped);
    BOOST_TEST(out.event == 1u);
    BOOST_TEST(out.t == rec.hits[1].t);
    BOOST_TEST(std::abs(x[0]) <= projectile_bound(out.stats.accepted, 1.0, 0.0) + 8 * eps * v0 * t_ground);
    BOOST_TEST(std::abs(x[1] + v0) <= 64 * eps * v0 + g_acc * projectile_bound(out.stats.accepted, v0, t_ground));
  }
}

// The pendulum theta'' = -w^2 sin(theta) released from rest at theta0: its period is
// T = 4 K(k) / w with k = sin(theta0 / 2), K the complete elliptic integral of the first kind,
// K(k) = pi / (2 AGM(1, sqrt(1 - k^2))). theta crosses zero downwards at T/4 + n T and upwards at
// 3T/4 + n T.
constexpr double w0 = 2.0, theta0 = 2.0;
double pendulum_period() { return test_support::pendulum_period(w0, theta0); }
struct PendulumRhs {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -w0 * w0 * std::sin(x[0]);
  }
};
struct PendulumAcc {
  void operator()(double, const rt::State<double>& q, rt::State<double>& a) const { a[0] = -w0 * w0 * std::sin(q[0]); }
};
struct PendulumEvents {
  void operator()(double, const rt::State<double>& x, rt::State<double>& out) const { out[0] = x[0]; }
};

// Bound on a crossing time, derived from the integration's own accuracy: every step commits a local
// error of at most `local` per component (the tolerance times the error scale for an accepted
// adaptive step; measured below for the fixed-step method). For the pendulum an error in the
// state shifts the energy and so the period, which turns into a phase error growing linearly: over
// time t the N local errors add to at most N * local * (1 + |dT/dE| * max|dE/dx| * t / T) in the
// phase, here with |dT/dE| * |dE/dx| / T <= 1 for theta0 = 2, w = 2 (T = 4.07, dT/dtheta0 = 1.3,
// dtheta0/dE = 1/(w^2 sin theta0) = 0.27). At the crossing |theta'| = 2 w sin(theta0/2) = 3.37
// converts the phase error into time.
double pendulum_bound(std::size_t steps, double local, double t) {
  const double slope = 2 * w0 * std::sin(theta0 / 2);
  return double(steps) * local * (1 + t) / slope + 4 * eps * t;
}

}  // namespace

BOOST_AUTO_TEST_CASE(brent_finds_a_root_to_the_last_bits) {
  int evals = 0;
  const double r = rt::brent_root(
      [&](double x) {
        ++evals;
        return std::cos(x);
      },
      0.0, 2.0, 1.0, std::cos(2.0));
  BOOST_TEST(std::abs(r - pi / 2) <= 4 * eps * pi / 2, "root " << r);
  BOOST_TEST(evals < 20);
  // A root at an end is returned as is; no sign change is refused.
  BOOST_TEST(rt::brent_root([](double x) { return x; }, 0.0, 1.0, 0.0, 1.0) == 0.0);
  BOOST_CHECK_THROW(rt::brent_root([](double x) { return x; }, 1.0, 2.0, 1.0, 2.0), std::invalid_argument);
}

BOOST_AUTO_TEST_CASE(projectile_apex_and_ground_with_every_method) {
  ProjectileRhs rhs;
  ProjectileAcc acc;
  ProjectileEvents ev;
  const rt::Tolerances tol{1e-12, 1e-12};
  const double t_end = 10.0, h = 0.01;
  auto adaptive = [&](auto stepper) {
    return [&, stepper](rt::State<double>& x, rt::EventLocator<double>& loc, Recorder& rec) mutable {
      return rt::integrate_adaptive_events(stepper, rhs, x, 0.0, t_end, 0.0, tol, loc, ev,
                                           [](double, const rt::State<double>&) {}, rec);
    };
  };
  auto fixed = [&](auto stepper, auto& sys) {
    return [&, stepper](rt::State<double>& x, rt::EventLocator<double>& loc, Recorder& rec) mutable {
      return rt::integrate_fixed_events(stepper, sys, x, 0.0, t_end, h, loc, ev,
                                        [](double, const rt::State<double>&) {}, rec);
    };
  };
  check_projectile("dopri5", adaptive(rt::Dopri5<double>{}));
  check_projectile("dop853", adaptive(rt::Dop853<double>{}));
  check_projectile("rk4", fixed(rt::Rk4<double>{}, rhs));
  check_projectile("gl4", fixed(rt::Gl4<double>{}, rhs));
  check_projectile("gl6", fixed(rt::Gl6<double>{}, rhs));
  check_projectile("gl8", fixed(rt::Gl8<double>{}, rhs));
  check_projectile("verlet", fixed(rt::Verlet<double>{}, acc));
  check_projectile("yoshida6", fixed(rt::Yoshida6<double>{}, acc));
  check_projectile("kahanli8", fixed(rt::KahanLi8<double>{}, acc));
}

BOOST_AUTO_TEST_CASE(observer_rows_are_in_time_order_and_stop_at_the_terminal_event) {
  ProjectileRhs rhs;
  ProjectileEvents ev;
  rt::State<double> x{0.0, v0};
  rt::EventLocator<double> loc(projectile_specs(true));
  std::vector<double> times;
  bool sorted = true;
  rt::Rk4<double> stepper;
  const auto outcome = rt::integrate_fixed_events(
      stepper, rhs, x, 0.0, 10.0, 0.1, loc, ev,
      [&](double t, const rt::State<double>&) {
        sorted = sorted && (times.empty() || t >= times.back());
        times.push_back(t);
      },
      [&](const rt::EventHit<double>& hit) {
        sorted = sorted && (times.empty() || hit.t >= times.back());
        times.push_back(hit.t);
      });
  BOOST_TEST(sorted);
  BOOST_TEST(outcome.stopped);
  BOOST_TEST(times.back() == outcome.t);
  // No step past the ground: the last observed step ends before it.
  BOOST_TEST(times[times.size() - 2] < outcome.t);
  BOOST_TEST(outcome.stats.accepted == std::size_t(std::ceil(outcome.t / 0.1)));
}

BOOST_AUTO_TEST_CASE(a_ground_event_at_the_start_is_not_a_crossing) {
  // y = 0 at launch: g starts at zero and is armed once it leaves it, so only the landing counts.
  ProjectileRhs rhs;
  ProjectileEvents ev;
  rt::State<double> x{0.0, v0};
  rt::EventLocator<double> loc({{rt::EventDirection::both, false}, {rt::EventDirection::both, false}});
  Recorder rec;
  rt::Dopri5<double> st;
  rt::integrate_adaptive_events(st, rhs, x, 0.0, 2 * v0 / g_acc + 0.5, 0.0, {1e-10, 1e-10}, loc, ev,
                                [](double, const rt::State<double>&) {}, rec);
  BOOST_REQUIRE_EQUAL(rec.hits.size(), 2u);
  BOOST_TEST(rec.hits[0].index == 0u);
  BOOST_TEST(rec.hits[1].index == 1u);
  BOOST_TEST(rec.hits[1].direction == -1);
}

BOOST_AUTO_TEST_CASE(pendulum_zero_crossings_at_quarter_periods) {
  const double T = pendulum_period();
  const int periods = 5;
  const double t_end = periods * T;
  PendulumRhs rhs;
  PendulumAcc acc;
  PendulumEvents ev;
  auto check = [&](const std::string& method, const std::vector<rt::EventHit<double>>& hits, rt::EventDirection dir,
                   std::size_t steps, double local) {
    BOOST_TEST_CONTEXT(method) {
      // both: T/4, 3T/4, 5T/4, ...; down only: T/4 + nT.
      const std::size_t expected = dir == rt::EventDirection::both ? 2 * periods : periods;
      BOOST_REQUIRE_EQUAL(hits.size(), expected);
      double worst = 0;
      for (std::size_t k = 0; k < hits.size(); ++k) {
        const double quarter = dir == rt::EventDirection::both ? double(2 * k + 1) : double(4 * k + 1);
        const double exact = quarter * T / 4;
        const int want_dir = dir == rt::EventDirection::down ? -1 : (k % 2 == 0 ? -1 : 1);
        BOOST_TEST(hits[k].direction == want_dir);
        const double err = std::abs(hits[k].t - exact);
        worst = std::max(worst, err);
        BOOST_TEST(err <= pendulum_bound(steps, local, exact), "crossing " << k << " at " << hits[k].t << " vs "
                                                                          << exact << " (error " << err << ")");
        // g = theta itself: zero up to the root's bracket (4 eps t) times |theta'| <= 3.4, and round-off.
        BOOST_TEST(std::abs(hits[k].x[0]) <= 3.4 * 4 * eps * exact + 16 * eps);
      }
      BOOST_TEST_MESSAGE(method << ": worst crossing error " << worst << " s over " << steps << " steps");
    }
  };
  for (rt::EventDirection dir : {rt::EventDirection::both, rt::EventDirection::down}) {
    {
      // Accepted steps have a local error <= tol * (1 + |x|) per component, |x| <= 3.4 here.
      const double tol = 1e-13;
      rt::State<double> x{theta0, 0.0};
      rt::EventLocator<double> loc({{dir, false}});
      Recorder rec;
      rt::Dop853<double> st;
      const auto out = rt::integrate_adaptive_events(st, rhs, x, 0.0, t_end, 0.0, {tol, tol}, loc, ev,
                                                     [](double, const rt::State<double>&) {}, rec);
      check("dop853", rec.hits, dir, out.stats.accepted, tol * 4.4);
    }
    {
      const double tol = 1e-12;
      rt::State<double> x{theta0, 0.0};
      rt::EventLocator<double> loc({{dir, false}});
      Recorder rec;
      rt::Dopri5<double> st;
      const auto out = rt::integrate_adaptive_events(st, rhs, x, 0.0, t_end, 0.0, {tol, tol}, loc, ev,
                                                     [](double, const rt::State<double>&) {}, rec);
      // The dense output is one order below the step (O(h^5) locally against the tolerance-sized
      // O(h^5) error estimate of the fourth-order embedded solution): the same bound holds.
      check("dopri5", rec.hits, dir, out.stats.accepted, tol * 4.4);
    }
    {
      // Gauss-Legendre 8 with h = T/200: the local error of one step, measured against a step of
      // 1/16 of it (which is 16^9 times more accurate), bounds `local`.
      const double h = T / 200;
      rt::State<double> a{theta0, 0.0}, b = a;
      rt::Gl8<double> big, small;
      big.do_step(rhs, a, 0.0, h);
      for (int i = 0; i < 16; ++i) small.do_step(rhs, b, i * h / 16, h / 16);
      const double local = std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1])) + 16 * eps * 4;
      rt::State<double> x{theta0, 0.0};
      rt::EventLocator<double> loc({{dir, false}});
      Recorder rec;
      rt::Gl8<double> st;
      const auto out = rt::integrate_fixed_events(st, rhs, x, 0.0, t_end, h, loc, ev,
                                                  [](double, const rt::State<double>&) {}, rec);
      check("gl8", rec.hits, dir, out.stats.accepted, local);
    }
    {
      const double h = T / 200;
      rt::State<double> a{theta0, 0.0}, b = a;
      rt::KahanLi8<double> big, small;
      big.do_step(acc, a, 0.0, h);
      for (int i = 0; i < 16; ++i) small.do_step(acc, b, i * h / 16, h / 16);
      const double local = std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1])) + 16 * eps * 4;
      rt::State<double> x{theta0, 0.0};
      rt::EventLocator<double> loc({{dir, false}});
      Recorder rec;
      rt::KahanLi8<double> st;
      const auto out = rt::integrate_fixed_events(st, acc, x, 0.0, t_end, h, loc, ev,
                                                  [](double, const rt::State<double>&) {}, rec);
      check("kahanli8", rec.hits, dir, out.stats.accepted, local);
    }
  }
}

// The summation alone. With a constant rate x' = c every stage derivative is c, so each method's
// increment is one and the same double d = fl(h * sum b_i c) every step, and in exact arithmetic
// the method gives x_n = x_0 + n d, which long double computes to ~1e-19 relative (n d needs 71
// bits, long double has 64). (An oscillator would not isolate the summation: rounding the
// tableau's coefficients to double perturbs the method itself by O(eps) per step, a phase drift
// of t eps that no summation removes.) Plain x += d rounds by up to ulp(x)/2 per step, here a
// systematic error since d and the leading bits of x repeat: of order n ulp(x)/4 ~ 2e-9 for
// n = 2e5, x ~ 2000. Compensated, the lost bits are carried into the next step, so the result is
// within an ulp or two of x_0 + n d. The assertion: compensated within 2 ulp(x_n), and plain
// worse by more than a factor 100 (its error is ~1e4 ulp).
struct Drift {
  template <class S>
  void operator()(S, const rt::State<S>&, rt::State<S>& d) const {
    d[0] = S(1) / S(3);
    d[1] = S(-2) / S(7);
  }
};

template <class Make>
void compensation_helps(const std::string& method, Make make) {
  const int n = 200000;
  const double h = 0.01;
  auto run = [&](bool compensated) {
    auto st = make();
    st.set_compensated(compensated);
    rt::State<double> x{0.1, 0.2};
    Drift drift;
    for (int k = 0; k < n; ++k) st.do_step(drift, x, k * h, h);
    return x;
  };
  // d, exactly as the method forms it: one step from 0.
  auto first = make();
  rt::State<double> d{0.0, 0.0};
  Drift drift;
  first.do_step(drift, d, 0.0, h);
  auto error = [&](const rt::State<double>& x) {
    long double worst = 0;
    const double x0[2] = {0.1, 0.2};
    for (int i = 0; i < 2; ++i) {
      const long double exact = (long double)x0[i] + (long double)n * (long double)d[i];
      worst = std::max(worst, std::abs((long double)x[i] - exact) / (long double)std::abs(x[i]));
    }
    return double(worst / eps);  // in units of eps |x|, about ulps
  };
  const double plain = error(run(false)), compensated = error(run(true));
  BOOST_TEST_MESSAGE(method << ": summation error after " << n << " steps, in eps |x|: plain " << plain
                            << ", compensated " << compensated);
  BOOST_TEST(compensated <= 2.0, method << ": compensated " << compensated);
  BOOST_TEST(plain > 100 * std::max(compensated, 1.0), method << ": plain " << plain);
}

BOOST_AUTO_TEST_CASE(compensated_summation_reduces_round_off_of_explicit_methods) {
  compensation_helps("rk4", [] { return rt::Rk4<double>{}; });
  compensation_helps("dopri5", [] { return rt::Dopri5<double>{}; });
  compensation_helps("dop853", [] { return rt::Dop853<double>{}; });
}
