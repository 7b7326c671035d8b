// The event-driven hybrid driver (runtime/contact/event_driven.hpp) on the known answers of the
// unilateral-constraints chapter (Mei, Special Topics in Analytical Mechanics, ch. 6): the bouncing
// ball and its Zeno point, a pendulum against a wall (no Zeno) and leaning on one (Zeno, then the
// contact phase), a particle leaving a smooth sphere (contact phase from t = 0, separation) and
// the §6.7 ratchet (a kinematic constraint ẏ ≥ 0). Reference values computed with mpmath (30 digits).
#define BOOST_TEST_MODULE runtime_event_driven
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "eomc/runtime/contact/event_driven.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"

namespace rt = eomc::runtime;
namespace ct = eomc::runtime::contact;
using Vec = ct::Vector<double>;
using Mat = ct::Matrix<double>;

namespace {

constexpr double grav = 9.81;
const double eps = std::numeric_limits<double>::epsilon();
const double pi = std::acos(-1.0);
const rt::Tolerances tight{1e-12, 1e-14};

struct Run {
  std::vector<double> t;
  std::vector<Vec> lambda;
  std::vector<rt::State<double>> x;
  std::vector<std::vector<bool>> active;
};

template <class System>
ct::EventDrivenOutcome<double> run(const System& sys, rt::State<double>& x, double t0, double t1, Run& rec,
                                   const ct::EventDrivenOptions<double>& options = {},
                                   const rt::Tolerances& tol = tight) {
  rt::Dopri5<double> stepper;
  return ct::integrate_event_driven(stepper, sys, x, t0, t1, tol,
                                    [&](double t, const rt::State<double>& xs, const Vec& l, const std::vector<bool>& a) {
                                      rec.t.push_back(t);
                                      rec.x.push_back(xs);
                                      rec.lambda.push_back(l);
                                      rec.active.push_back(a);
                                    },
                                    options);
}

std::vector<ct::ContactEvent<double>> of_kind(const ct::EventDrivenOutcome<double>& out, ct::ContactEventKind kind) {
  std::vector<ct::ContactEvent<double>> v;
  for (const auto& e : out.events)
    if (e.kind == kind) v.push_back(e);
  return v;
}

// One degree of freedom q with M = mass, f = force(q), one gap g = q − wall (position level).
ct::ContactSystem<double> one_dof(double mass, double (*force)(double), double wall, double restitution) {
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{restitution, ct::GapLevel::position}};
  sys.mass = [mass](double, const Vec&, Mat& M) { M(0, 0) = mass; };
  sys.force = [force](double, const Vec& q, const Vec&, Vec& f) { f[0] = force(q[0]); };
  sys.gaps = [wall](double, const Vec& q, const Vec&, Vec& g) { g[0] = q[0] - wall; };
  sys.rows = [](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    b[0] = 0.0;
  };
  return sys;
}

// ---- the bouncing ball: y'' = −g, gap y, e = 0.7, from y = 2 at rest -----------------------------
constexpr double ball_mass = 2.0, ball_e = 0.7, ball_h0 = 2.0;
double ball_force(double) { return -ball_mass * grav; }

// The bound on the impact times, as in tests/runtime/events/actions.cpp: between impacts the motion
// is quadratic, which dopri5 reproduces to round-off, so each impact carries the integrator's
// tolerance over the impact speed (at least e^(k−1) v1) plus Brent's bracket (8 ε t); an error dt
// in t_k moves the next flight time by 2 e dt, so the errors grow at most by (1 + 2e) per impact.
double ball_time_bound(double t_last, int count) {
  const double v_min = std::pow(ball_e, count - 1) * std::sqrt(2.0 * grav * ball_h0);
  const double per_impact = 8.0 * eps * t_last + (tight.rtol * ball_h0 + tight.atol) / v_min;
  double bound = 0.0;
  for (int k = 0; k < count; ++k) bound = bound * (1.0 + 2.0 * ball_e) + per_impact;
  return bound;
}

}  // namespace

BOOST_AUTO_TEST_CASE(bouncing_ball_impacts_and_energy) {
  const auto sys = one_dof(ball_mass, ball_force, 0.0, ball_e);
  rt::State<double> x{ball_h0, 0.0};
  Run rec;
  ct::EventDrivenOptions<double> options;
  options.detect_zeno = false;  // the 10th impact (3.498) comes after the Zeno test would fire
  const auto out = run(sys, x, 0.0, 3.52, rec, options);
  const auto hits = of_kind(out, ct::ContactEventKind::impact);
  BOOST_REQUIRE_EQUAL(hits.size(), 10u);
  const double known[] = {0.638550856814101, 1.53252205635384, 2.15830189603166};
  for (int k = 0; k < 3; ++k) {
    BOOST_TEST_MESSAGE("impact " << k + 1 << ": t = " << hits[std::size_t(k)].t << ", error "
                                 << hits[std::size_t(k)].t - known[k]);
    BOOST_TEST(std::abs(hits[std::size_t(k)].t - known[k]) <= ball_time_bound(known[k], k + 1) + 1e-14);
  }
  const double t10 = 3.49820498042809;
  BOOST_TEST_MESSAGE("impact 10: t = " << hits[9].t << ", error " << hits[9].t - t10 << ", bound "
                                       << ball_time_bound(t10, 10));
  BOOST_TEST(std::abs(hits[9].t - t10) <= ball_time_bound(t10, 10) + 1e-14);
  for (const auto& h : hits) {
    // Newton's law with e: ġ⁺ = −e ġ⁻ exactly in one dof; T⁺ = e² T⁻, and Carnot's prediction.
    const double T_minus = 0.5 * ball_mass * h.rate_before * h.rate_before;
    BOOST_TEST(h.rate_after == -ball_e * h.rate_before, boost::test_tools::tolerance(4 * eps));
    BOOST_TEST(h.energy_change == -(1.0 - ball_e * ball_e) * T_minus, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(h.carnot == h.energy_change, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(h.impulse == ball_mass * (1.0 + ball_e) * -h.rate_before, boost::test_tools::tolerance(4 * eps));
  }
  BOOST_TEST(of_kind(out, ct::ContactEventKind::zeno).empty());
}

BOOST_AUTO_TEST_CASE(bouncing_ball_zeno_then_rest) {
  const auto sys = one_dof(ball_mass, ball_force, 0.0, ball_e);
  rt::State<double> x{ball_h0, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 5.0, rec);
  const auto zeno = of_kind(out, ct::ContactEventKind::zeno);
  BOOST_REQUIRE_EQUAL(zeno.size(), 1u);
  const double t_inf = 3.61845485527991;
  // The ratios of the ball's flight times are exactly e: the extrapolation carries the error of
  // its last impact times (ball_time_bound), amplified by Δt ∂/∂t of the series, and its own bound.
  const int fired = int(of_kind(out, ct::ContactEventKind::impact).size());
  const double bound = ball_time_bound(t_inf, fired) * (1.0 + 2.0 / (1.0 - ball_e)) + zeno[0].extrapolation_error;
  BOOST_TEST_MESSAGE("Zeno after " << fired << " impacts: t = " << zeno[0].t << ", error " << zeno[0].t - t_inf
                                   << ", bound " << bound << ", r = " << zeno[0].ratio);
  BOOST_TEST(std::abs(zeno[0].t - t_inf) <= bound);
  BOOST_TEST(std::abs(zeno[0].ratio - ball_e) <= 1e-9);
  const auto contact = of_kind(out, ct::ContactEventKind::contact);
  BOOST_REQUIRE_EQUAL(contact.size(), 1u);
  BOOST_TEST(contact[0].t == zeno[0].t);
  BOOST_TEST(contact[0].lambda == ball_mass * grav, boost::test_tools::tolerance(4 * eps));
  // At rest on the floor: the Zeno limit is exact (y = 0, v = 0) and the contact phase keeps it.
  BOOST_TEST(x[0] == 0.0);
  BOOST_TEST(x[1] == 0.0);
  BOOST_TEST(out.active[0]);
  BOOST_TEST(out.lambda[0] == ball_mass * grav, boost::test_tools::tolerance(4 * eps));
  BOOST_TEST(rec.t.back() == 5.0);
}

// ---- a pendulum of length l: M = m l², f = −m g l sin θ ---------------------------------------
// e = 0.6 for the leaning pendulum. The amplitudes of the brief for the vertical wall (59.34°,
// 40.54°, 28.07°) are those of e = 0.7: energy after impact k is e^(2k) of the drop's, so
// 1 − cos A_k = e^(2k) (1 − cos 90°), and cos 59.336° = 1 − 0.49; with e = 0.6 they would be
// 50.21°, 29.49°, 17.57°. The vertical-wall case runs with 0.7; the first impact does not depend on e.
constexpr double pend_l = 0.5, pend_m = 1.0, pend_e = 0.6, vertical_e = 0.7;
double pendulum_force(double theta) { return -pend_m * grav * pend_l * std::sin(theta); }

// The complete elliptic integral K(k) by the arithmetic-geometric mean: K = π / (2 AGM(1, √(1 − k²))).
double elliptic_k(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 40 && std::abs(a - b) > 4 * eps * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return pi / (2.0 * a);
}

BOOST_AUTO_TEST_CASE(pendulum_against_a_vertical_wall) {
  const auto sys = one_dof(pend_m * pend_l * pend_l, pendulum_force, 0.0, vertical_e);
  rt::State<double> x{pi / 2, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 8.0, rec);
  const auto hits = of_kind(out, ct::ContactEventKind::impact);
  BOOST_REQUIRE_GE(hits.size(), 8u);
  BOOST_TEST(of_kind(out, ct::ContactEventKind::zeno).empty());
  // The first impact: a quarter period of the 90° pendulum, located on the dense output; the
  // integrator's global error over ~0.4 s at rtol 1e-12 is well below 1e-11 in t and θ̇.
  BOOST_TEST_MESSAGE("first impact t = " << hits[0].t << ", |ġ⁻| = " << -hits[0].rate_before);
  BOOST_TEST(std::abs(hits[0].t - 0.41857927447728) <= 1e-11);
  BOOST_TEST(std::abs(-hits[0].rate_before - 6.26418390534633) <= 1e-10);
  // Amplitudes after each impact from energy: ½ m l² θ̇⁺² = m g l (1 − cos A).
  const double amplitude_deg[] = {59.336170257614, 40.5446170970667, 28.0727232800295};
  for (int k = 0; k < 3; ++k) {
    const double w = hits[std::size_t(k)].rate_after;
    const double A = std::acos(1.0 - pend_l * w * w / (2.0 * grav)) * 180.0 / pi;
    BOOST_TEST_MESSAGE("amplitude " << k + 1 << ": " << A << "°, error " << A - amplitude_deg[k]);
    BOOST_TEST(std::abs(A - amplitude_deg[k]) <= 1e-9);
  }
  // Each interval is the half period for the amplitude after the impact that opens it,
  // 2 √(l/g) K(sin(A/2)), which tends to π √(l/g): no geometric accumulation.
  for (std::size_t k = 1; k < hits.size(); ++k) {
    const double w = hits[k - 1].rate_after;
    const double A = std::acos(1.0 - pend_l * w * w / (2.0 * grav));
    const double half = 2.0 * std::sqrt(pend_l / grav) * elliptic_k(std::sin(A / 2));
    BOOST_TEST(std::abs(hits[k].t - hits[k - 1].t - half) <= 1e-10);
  }
  const double limit = pi * std::sqrt(pend_l / grav);
  const double last = hits.back().t - hits[hits.size() - 2].t;
  BOOST_TEST_MESSAGE(hits.size() << " impacts; last interval " << last << " vs π√(l/g) = " << limit);
  BOOST_TEST(std::abs(last - limit) <= 1e-3 * limit);
}

constexpr double wall_deg = 10.0;
BOOST_AUTO_TEST_CASE(pendulum_leaning_on_a_wall_zeno_then_contact) {
  const double wall = wall_deg * pi / 180.0;
  const auto sys = one_dof(pend_m * pend_l * pend_l, pendulum_force, wall, pend_e);
  rt::State<double> x{30.0 * pi / 180.0, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 3.0, rec);
  const auto zeno = of_kind(out, ct::ContactEventKind::zeno);
  BOOST_REQUIRE_EQUAL(zeno.size(), 1u);
  const double t_inf = 1.76155662459086;
  BOOST_TEST_MESSAGE("Zeno at " << zeno[0].t << ", error " << zeno[0].t - t_inf << ", extrapolation bound "
                                << zeno[0].extrapolation_error << ", r = " << zeno[0].ratio << " after "
                                << of_kind(out, ct::ContactEventKind::impact).size() << " impacts");
  // Besides the extrapolation's own estimate, t∞ carries the integrator's error in the impact
  // states: near the limit t∞ ≈ t_k + 2 v_k⁺ / (a (1 − e)), a = g/l sin 10° the gap's deceleration,
  // and each of the impacts passes on a speed error of at most rtol |θ̇|max + atol (|θ̇| ≤ 2.2 rad/s
  // here, the speed at the first impact).
  const std::size_t fired = of_kind(out, ct::ContactEventKind::impact).size();
  const double a = grav / pend_l * std::sin(wall);
  const double integration = 2.0 / (a * (1.0 - pend_e)) * double(fired) * (tight.rtol * 2.2 + tight.atol);
  BOOST_TEST_MESSAGE("bound " << zeno[0].extrapolation_error + integration);
  BOOST_TEST(std::abs(zeno[0].t - t_inf) <= zeno[0].extrapolation_error + integration);
  // λ is the wall's generalized force on θ, a torque about the pivot (gap in radians, W = 1):
  // at rest against the wall λ = m g l sin 10°, so λ/m = g l sin 10° in m²/s².
  BOOST_TEST(x[0] == wall, boost::test_tools::tolerance(4 * eps));
  BOOST_TEST(x[1] == 0.0);
  BOOST_TEST(out.active[0]);
  BOOST_TEST(out.lambda[0] / pend_m == 0.851744311456293, boost::test_tools::tolerance(1e-14));
}

// ---- a particle on a smooth sphere of radius R, q = (x, y), leaving the top with v0 ------------
BOOST_AUTO_TEST_CASE(particle_leaves_a_smooth_sphere) {
  static constexpr double R = 2.0, v0 = 1.5, mass = 1.0;
  ct::ContactSystem<double> sys;
  sys.dof = 2;
  sys.contacts = {{0.0, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M = mass * Mat::Identity(2, 2); };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f << 0.0, -mass * grav; };
  sys.gaps = [](double, const Vec& q, const Vec&, Vec& g) { g[0] = q.norm() - R; };
  // g = |q| − R: W = qᵀ/|q|, g̈ = W u̇ + (|u|² − (n·u)²)/|q|.
  sys.rows = [](double, const Vec& q, const Vec& u, Mat& W, Vec& b) {
    const double r = q.norm();
    W.row(0) = q.transpose() / r;
    const double un = q.dot(u) / r;
    b[0] = (u.squaredNorm() - un * un) / r;
  };
  rt::State<double> x{0.0, R, v0, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 1.2, rec);
  const auto contact = of_kind(out, ct::ContactEventKind::contact);
  const auto sep = of_kind(out, ct::ContactEventKind::separation);
  BOOST_REQUIRE_EQUAL(contact.size(), 1u);
  BOOST_REQUIRE_EQUAL(sep.size(), 1u);
  BOOST_TEST(contact[0].t == 0.0);
  BOOST_TEST(contact[0].lambda == mass * (grav - v0 * v0 / R), boost::test_tools::tolerance(4 * eps));
  BOOST_TEST(of_kind(out, ct::ContactEventKind::impact).empty());
  // The state where λ reaches zero (the observer's record at the separation time).
  std::size_t at = 0;
  for (std::size_t i = 0; i < rec.t.size(); ++i)
    if (rec.t[i] == sep[0].t) at = i;
  const double cos_theta = rec.x[at][1] / std::hypot(rec.x[at][0], rec.x[at][1]);
  BOOST_TEST_MESSAGE("separation t = " << sep[0].t << " (error " << sep[0].t - 0.717367168216632 << "), cos θ = "
                                       << cos_theta << " (error " << cos_theta - 0.704892966360856 << ")");
  BOOST_TEST(std::abs(sep[0].t - 0.717367168216632) <= 1e-10);
  BOOST_TEST(std::abs(cos_theta - 0.704892966360856) <= 1e-10);
  BOOST_TEST(!out.active[0]);
  BOOST_TEST(x[2] * x[0] > 0.0);
  // Through the contact phase the particle stayed on the sphere to round-off (the projection after
  // every step); the separation state comes from the dense output inside a step, off the sphere by
  // the step's local error, below rtol R + atol.
  for (std::size_t i = 0; i < at; ++i)
    BOOST_TEST(std::abs(std::hypot(rec.x[i][0], rec.x[i][1]) - R) <= 8 * eps * R);
  BOOST_TEST(std::abs(std::hypot(rec.x[at][0], rec.x[at][1]) - R) <= tight.rtol * R + tight.atol);
}

// ---- §6.7 ratchet: ÿ = −4y, the kinematic constraint ẏ ≥ 0 ----------------------------------
BOOST_AUTO_TEST_CASE(ratchet_kinematic_constraint) {
  static constexpr double mass = 3.0;
  ct::ContactSystem<double> sys;
  sys.dof = 1;
  sys.contacts = {{0.0, ct::GapLevel::velocity}};
  sys.mass = [](double, const Vec&, Mat& M) { M(0, 0) = mass; };
  sys.force = [](double, const Vec& q, const Vec&, Vec& f) { f[0] = -4.0 * mass * q[0]; };
  sys.gaps = [](double, const Vec&, const Vec& u, Vec& g) { g[0] = u[0]; };
  sys.rows = [](double, const Vec&, const Vec&, Mat& W, Vec& b) {
    W(0, 0) = 1.0;
    b[0] = 0.0;
  };
  rt::State<double> x{-1.0, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 3.0, rec);
  // Free (y = −cos 2t, ẏ = 2 sin 2t ≥ 0) until ẏ returns to zero at π/2, then held at y = 1.
  const auto contact = of_kind(out, ct::ContactEventKind::contact);
  BOOST_REQUIRE_EQUAL(contact.size(), 1u);
  BOOST_TEST_MESSAGE("held from t = " << contact[0].t << " (error " << contact[0].t - pi / 2 << "), λ = "
                                      << contact[0].lambda);
  // ẏ ∝ (t − π/2) near π/2, so t carries the integrator's error in ẏ over |ÿ| = 4.
  BOOST_TEST(std::abs(contact[0].t - pi / 2) <= 1e-11);
  BOOST_TEST(contact[0].lambda == 4.0 * mass, boost::test_tools::tolerance(1e-11));
  BOOST_TEST(of_kind(out, ct::ContactEventKind::impact).empty());
  BOOST_TEST(std::abs(x[0] - 1.0) <= 1e-11);
  BOOST_TEST(x[1] == 0.0);
  BOOST_TEST(out.lambda[0] == 4.0 * mass * x[0], boost::test_tools::tolerance(4 * eps));
}

// ---- several contacts: a rod (length L, q = (y, φ)) falling flat onto the floor ---------------
// Both ends touch at once: the impact and the contact phase go through the LCP (solve_lcp).
// By symmetry φ stays 0 and the centre bounces like the ball: the same impact times and Zeno point
// from the same drop height, each end takes half the impulse, and at rest λ = (m g/2, m g/2).
BOOST_AUTO_TEST_CASE(rod_falling_flat_two_contacts) {
  static constexpr double L = 1.0, mass = ball_mass, inertia = mass * L * L / 12.0;
  ct::ContactSystem<double> sys;
  sys.dof = 2;
  sys.contacts = {{ball_e, ct::GapLevel::position}, {ball_e, ct::GapLevel::position}};
  sys.mass = [](double, const Vec&, Mat& M) { M << mass, 0.0, 0.0, inertia; };
  sys.force = [](double, const Vec&, const Vec&, Vec& f) { f << -mass * grav, 0.0; };
  // The ends' heights y ∓ (L/2) sin φ.
  sys.gaps = [](double, const Vec& q, const Vec&, Vec& g) {
    g << q[0] - 0.5 * L * std::sin(q[1]), q[0] + 0.5 * L * std::sin(q[1]);
  };
  sys.rows = [](double, const Vec& q, const Vec& u, Mat& W, Vec& b) {
    const double c = 0.5 * L * std::cos(q[1]), s = 0.5 * L * std::sin(q[1]);
    W << 1.0, -c, 1.0, c;
    b << s * u[1] * u[1], -s * u[1] * u[1];
  };
  rt::State<double> x{ball_h0, 0.0, 0.0, 0.0};
  Run rec;
  const auto out = run(sys, x, 0.0, 5.0, rec);
  const auto hits = of_kind(out, ct::ContactEventKind::impact);
  BOOST_REQUIRE_GE(hits.size(), 2u);
  // Impact k reports both ends, each with half the ball's impulse.
  BOOST_TEST(hits[0].contact == 0u);
  BOOST_TEST(hits[1].contact == 1u);
  BOOST_TEST(hits[1].t == hits[0].t);
  BOOST_TEST(std::abs(hits[0].t - 0.638550856814101) <= ball_time_bound(0.638550856814101, 1) + 1e-14);
  for (const auto& h : hits) {
    BOOST_TEST(h.rate_after == -ball_e * h.rate_before, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(h.impulse == 0.5 * mass * (1.0 + ball_e) * -h.rate_before, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(h.carnot == h.energy_change, boost::test_tools::tolerance(1e-13));
  }
  const auto zeno = of_kind(out, ct::ContactEventKind::zeno);
  BOOST_REQUIRE_EQUAL(zeno.size(), 1u);
  BOOST_TEST_MESSAGE("rod: Zeno at " << zeno[0].t << ", error " << zeno[0].t - 3.61845485527991 << " after "
                                     << hits.size() << " impact records");
  const int fired = int(hits.size() / 2);
  BOOST_TEST(std::abs(zeno[0].t - 3.61845485527991) <=
             ball_time_bound(3.61845485527991, fired) * (1.0 + 2.0 / (1.0 - ball_e)) + zeno[0].extrapolation_error);
  BOOST_TEST(out.active[0]);
  BOOST_TEST(out.active[1]);
  BOOST_TEST(out.lambda[0] == 0.5 * mass * grav, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(out.lambda[1] == 0.5 * mass * grav, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(std::abs(x[0]) <= 1e-15);
  BOOST_TEST(std::abs(x[1]) <= 1e-15);
}
