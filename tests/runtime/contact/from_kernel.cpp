// contact/from_kernel.hpp: a kernel compiled into the program (the bundled generated/ kernels) as
// the ContactSystem both contact drivers take. The knife-edge sled hitting a wall (Mei §6.6; its
// scene derives the answer: at t = 0.5/√3 the wall's impulse P = 2√3 turns (ẋ, ẏ) = (−√3, −1) into
// (√3/2, 1/2) along the blade, T⁺ − T⁻ = −3/2 = Carnot's loss) through both drivers; the bouncing
// ball's first impact at √(2 h0 / g); the vibrating table's gap moving with the table.
#define BOOST_TEST_MODULE runtime_contact_from_kernel
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "ball_vibrating_table.hpp"
#include "bouncing_ball.hpp"
#include "eomc/runtime/contact/event_driven.hpp"
#include "eomc/runtime/contact/from_kernel.hpp"
#include "eomc/runtime/contact/moreau_jean.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "knife_edge_sled_wall.hpp"

namespace rt = eomc::runtime;
namespace rc = eomc::runtime::contact;
namespace models = eomc::models;

namespace {

using Vec = rc::Vector<double>;
using Mat = rc::Matrix<double>;

const double eps = std::numeric_limits<double>::epsilon();

template <class K>
rt::State<double> initial_state() {
  return rt::State<double>(K::initial_state.begin(), K::initial_state.end());
}

struct Impacts {
  std::vector<rc::ContactEvent<double>> events;
  rt::State<double> x_after;  // the state observed right after the first impact
};

// The event-driven driver (dopri5 at rtol = atol = tol) to t_end, the events and the state after
// the first impact.
Impacts event_driven(const rc::ContactSystem<double>& sys, rt::State<double> x, double t_end, double tol) {
  Impacts out;
  rc::EventDrivenOptions<double> options;
  options.on_event = [&](const rc::ContactEvent<double>& e) { out.events.push_back(e); };
  rt::Dopri5<double> stepper;
  rc::integrate_event_driven(stepper, sys, x, 0.0, t_end, rt::Tolerances{tol, tol},
                             [&](double, const rt::State<double>& xs, const Vec&, const std::vector<bool>&) {
                               if (out.x_after.empty() && !out.events.empty()) out.x_after = xs;
                             },
                             options);
  return out;
}

Impacts moreau_jean(const rc::ContactSystem<double>& sys, rt::State<double> x, double t_end, double h) {
  Impacts out;
  rt::integrate_moreau_jean<double>(
      sys, 0.0, t_end, h, 0.5, x,
      [&](double, const rt::State<double>& xs, const Vec&, const std::vector<bool>&) {
        if (out.x_after.empty() && !out.events.empty()) out.x_after = xs;
      },
      [&](const rc::ContactEvent<double>& e) { out.events.push_back(e); });
  return out;
}

}  // namespace

// The blocks are the kernel's: M, f, the gap, W and the bilateral rows at the initial state.
BOOST_AUTO_TEST_CASE(the_system_holds_the_kernels_blocks) {
  using K = models::KnifeEdgeSledWall;
  const K::Parameters p{};
  const rc::ContactSystem<double> sys = rc::contact_system<double>(rc::KernelContactBlocks<K>{p});
  BOOST_TEST(sys.dof == 3);
  BOOST_TEST_REQUIRE(sys.contacts.size() == 1u);
  BOOST_TEST(sys.contacts[0].restitution == 0.5);
  BOOST_TEST((sys.contacts[0].level == rc::GapLevel::position));
  BOOST_TEST_REQUIRE(sys.bilateral_holonomic.size() == 1u);
  BOOST_TEST(!sys.bilateral_holonomic[0]);  // the blade is a kinematic row
  BOOST_TEST(!sys.time_rates);              // a fixed wall
  const rt::State<double> x = initial_state<K>();
  Vec q(3), u(3), g(1), f(3), b(1), bf, phi, r;
  for (int i = 0; i < 3; ++i) q[i] = x[std::size_t(i)], u[i] = x[std::size_t(3 + i)];
  Mat M(3, 3), W(1, 3), C;
  sys.mass(0.0, q, M);
  BOOST_TEST(M(0, 0) == 1.0);
  BOOST_TEST(M(2, 2) == 0.1);
  BOOST_TEST(M(0, 1) == 0.0);
  sys.gaps(0.0, q, u, g);
  BOOST_TEST(g[0] == 0.5);
  sys.rows(0.0, q, u, W, b);
  BOOST_TEST(W(0, 0) == 1.0);
  BOOST_TEST(W(0, 1) == 0.0);
  sys.bilateral(0.0, q, u, bf, phi, C, r);
  BOOST_TEST_REQUIRE(C.rows() == 1);
  BOOST_TEST(std::abs(C(0, 0) + 0.5) <= eps);  // −sin 30°
  BOOST_TEST(std::abs(phi[0]) <= 4 * eps);     // the start moves along the blade
}

// The sled through both drivers: Newton's law on the wall's normal with the blade holding.
BOOST_AUTO_TEST_CASE(the_sled_hits_the_wall_through_both_drivers) {
  using K = models::KnifeEdgeSledWall;
  const K::Parameters p{};
  const rc::ContactSystem<double> sys = rc::contact_system<double>(rc::KernelContactBlocks<K>{p});
  const double t_hit = 0.5 / std::sqrt(3.0), root3 = std::sqrt(3.0);
  // Event-driven: the impact located to the tolerance (free flight is linear: exact up to the
  // locator's rtol |t| + atol), the jump by the constrained Newton law to round-off.
  const double tol = 1e-12;
  const Impacts ed = event_driven(sys, initial_state<K>(), 1.0, tol);
  BOOST_TEST_REQUIRE(!ed.events.empty());
  const auto& hit = ed.events.front();
  BOOST_TEST((hit.kind == rc::ContactEventKind::impact));
  BOOST_TEST(std::abs(hit.t - t_hit) <= 10 * (tol * t_hit + tol));
  // No force acts: the velocities are exact up to the stepper's and the impact's rounding.
  const double round = 64 * eps * 2.0;
  BOOST_TEST(std::abs(hit.rate_before + root3) <= round);
  BOOST_TEST(std::abs(hit.rate_after - root3 / 2) <= round);
  BOOST_TEST(std::abs(hit.impulse - 2 * root3) <= 2 * round);
  BOOST_TEST(std::abs(hit.energy_change + 1.5) <= 2 * round * 2.0);
  BOOST_TEST(std::abs(hit.carnot + 1.5) <= 2 * round * 2.0);
  BOOST_TEST_REQUIRE(ed.x_after.size() == 6u);
  BOOST_TEST(std::abs(ed.x_after[3] - root3 / 2) <= round);
  BOOST_TEST(std::abs(ed.x_after[4] - 0.5) <= round);
  BOOST_TEST(std::abs(ed.x_after[5]) <= round);
  // Moreau–Jean: no force acts, so the step's law u⁺ = −e u⁻ on the normal with the blade held
  // (M̃⁻¹) is the same jump, found in the step within 1.5 h of the hit.
  const double h = 1e-3;
  const Impacts mj = moreau_jean(sys, initial_state<K>(), 1.0, h);
  BOOST_TEST_REQUIRE(!mj.events.empty());
  const auto& step = mj.events.front();
  BOOST_TEST((step.kind == rc::ContactEventKind::impact));
  BOOST_TEST(std::abs(step.t - t_hit) <= 1.5 * h);
  BOOST_TEST(std::abs(step.rate_after - root3 / 2) <= 1e-12);
  BOOST_TEST(std::abs(step.impulse - 2 * root3) <= 1e-12);
  BOOST_TEST(std::abs(step.energy_change + 1.5) <= 1e-12);
  BOOST_TEST(std::abs(step.carnot + 1.5) <= 1e-12);
  for (const auto& e : mj.events) BOOST_TEST((e.kind == rc::ContactEventKind::impact));  // one bounce, then away
  BOOST_TEST(mj.events.size() == 1u);
}

// The bouncing ball's first impact at t_1 = √(2 h0 / g) at v = g t_1, by the event-driven driver.
BOOST_AUTO_TEST_CASE(the_bouncing_ball_kernel_hits_the_floor_at_t1) {
  using K = models::BouncingBall;
  const K::Parameters p{};
  const rc::ContactSystem<double> sys = rc::contact_system<double>(rc::KernelContactBlocks<K>{p});
  const double t1 = std::sqrt(2 * 2.0 / 9.81), tol = 1e-12;
  const Impacts ed = event_driven(sys, initial_state<K>(), 1.0, tol);
  BOOST_TEST_REQUIRE(!ed.events.empty());
  // Free fall is a quadratic, which dopri5 integrates exactly: the impact time is the locator's
  // (10 (rtol t + atol)), and the speed g t carries that error, g · 10 (rtol t + atol).
  const double dt = 10 * (tol * t1 + tol);
  BOOST_TEST(std::abs(ed.events.front().t - t1) <= dt);
  BOOST_TEST(std::abs(ed.events.front().rate_before + 9.81 * t1) <= 9.81 * dt + 64 * eps * 9.81 * t1);
  BOOST_TEST(std::abs(ed.events.front().rate_after - 0.7 * 9.81 * t1) <= 0.7 * (9.81 * dt + 64 * eps * 9.81 * t1));
}

// The vibrating table's gap y − A sin ωt moves: the system has the kernel's time rates,
// w = −A ω cos ωt, and its gap follows the table.
BOOST_AUTO_TEST_CASE(the_vibrating_tables_gap_moves_with_the_table) {
  using K = models::BallVibratingTable;
  const K::Parameters p{};
  const rc::ContactSystem<double> sys = rc::contact_system<double>(rc::KernelContactBlocks<K>{p});
  BOOST_TEST_REQUIRE(static_cast<bool>(sys.time_rates));
  Vec q(1), u(1), w(1), g(1);
  q[0] = 0.3;
  u[0] = 0.0;
  for (double t : {0.0, 0.1, 0.37}) {
    sys.time_rates(t, q, w);
    sys.gaps(t, q, u, g);
    BOOST_TEST(std::abs(w[0] + p.A * p.omega * std::cos(p.omega * t)) <= 8 * eps);
    BOOST_TEST(std::abs(g[0] - (0.3 - p.A * std::sin(p.omega * t))) <= 8 * eps);
  }
}
