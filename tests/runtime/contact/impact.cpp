// contact/impact.hpp: Newton's impact law in Moreau's form. Known answers: a rod striking the floor
// with one end at 30° (closed form) and falling flat on both ends (the LCP), Newton's cradle under
// the simultaneous and the sequential law, the bouncing ball; on random multi-contact impacts the
// complementarity of the law and Carnot's energy balance, in double and long double.
#define BOOST_TEST_MODULE runtime_impact
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "eomc/runtime/contact/impact.hpp"

namespace rt = eomc::runtime;

namespace {

template <class S>
using Mat = rt::LcpMatrix<S>;
template <class S>
using Vec = rt::LcpVector<S>;

const double eps = std::numeric_limits<double>::epsilon();

// The rod: length 2l = 1, mass 1, I = m (2l)²/12 = 1/12 about the centre; coordinates (x, y, θ) of
// the centre and the angle θ of the rod below the horizontal, so that the end E = (x + l cos θ,
// y − l sin θ) is the lower one. Its gap is f = y − l sin θ, W = (0, 1, −l cos θ); the other end
// (x − l cos θ, y + l sin θ) has W = (0, 1, l cos θ).
const double l = 0.5, inertia = 1.0 / 12.0;

Mat<double> rod_mass() {
  Mat<double> M = Mat<double>::Zero(3, 3);
  M.diagonal() << 1.0, 1.0, inertia;
  return M;
}

}  // namespace

// θ = 30°, (v_x, v_y, ω)⁻ = (0, −2, 0), e = 1/2. G = 1 + l² cos²θ / I = 13/4, ḟ⁻ = −2:
// P = (1 + e)·2/G = 12/13, v_y⁺ = −2 + P = −14/13, ω⁺ = −l cos θ P / I = −36√3/13;
// T⁻ = 2, T⁺ = 260/169, ΔT = −78/169 = −(1/3) ½ G P² (Carnot).
BOOST_AUTO_TEST_CASE(rod_end_strikes_floor_at_30_degrees) {
  const double theta = std::acos(-1.0) / 6.0;
  Mat<double> W(1, 3);
  W << 0.0, 1.0, -l * std::cos(theta);
  Vec<double> u(3), e(1);
  u << 0.0, -2.0, 0.0;
  e << 0.5;
  const rt::ImpactResult<double> r = rt::newton_impact<double>(rod_mass(), W, e, u);
  BOOST_TEST(std::abs(r.P[0] - 0.923076923076923) <= 4 * eps);
  BOOST_TEST(r.u_plus[0] == 0.0);
  BOOST_TEST(std::abs(r.u_plus[1] - -1.07692307692308) <= 1e-14);
  BOOST_TEST(std::abs(r.u_plus[2] - -4.79644839019074) <= 1e-14);
  BOOST_TEST(std::abs(r.u_plus[1] + 14.0 / 13.0) <= 4 * eps);
  BOOST_TEST(std::abs(r.u_plus[2] + 36.0 * std::sqrt(3.0) / 13.0) <= 8 * eps);
  const double dT = r.kinetic_energy_after - r.kinetic_energy_before;
  BOOST_TEST(r.carnot_applies);
  BOOST_TEST(std::abs(dT + 78.0 / 169.0) <= 8 * eps);
  BOOST_TEST(std::abs(dT - r.carnot_prediction) <= 8 * eps);
  // Newton's law at the end: ḟ⁺ = −e ḟ⁻ = 1.
  BOOST_TEST(std::abs((W * r.u_plus)[0] - 1.0) <= 8 * eps);
}

// θ = 0, both ends strike at v_y = −2 with e = 1/2: G = [[4, −2], [−2, 4]], q = (−3, −3), the LCP
// gives P = (3/2, 3/2), u⁺ = (0, 1, 0); ΔT = −3/2 = −(1/3) · ½ · 3².
BOOST_AUTO_TEST_CASE(rod_falls_flat_on_both_ends) {
  Mat<double> W(2, 3);
  W << 0.0, 1.0, -l, 0.0, 1.0, l;
  Vec<double> u(3), e(2);
  u << 0.0, -2.0, 0.0;
  e << 0.5, 0.5;
  const rt::ImpactResult<double> r = rt::newton_impact<double>(rod_mass(), W, e, u);
  BOOST_TEST((r.status == rt::LcpStatus::solved));
  BOOST_TEST(std::abs(r.P[0] - 1.5) <= 8 * eps);
  BOOST_TEST(std::abs(r.P[1] - 1.5) <= 8 * eps);
  BOOST_TEST(std::abs(r.u_plus[1] - 1.0) <= 8 * eps);
  BOOST_TEST(std::abs(r.u_plus[2]) <= 8 * eps);
  BOOST_TEST(std::abs(r.kinetic_energy_after - r.kinetic_energy_before + 1.5) <= 8 * eps);
  BOOST_TEST(std::abs(r.carnot_prediction + 1.5) <= 8 * eps);
}

// Three equal balls touching, the first at v = 1, e = 1; gaps x₂ − x₁ − 2r and x₃ − x₂ − 2r.
// Simultaneous (Moreau): G = [[2, −1], [−1, 2]], q = (−2, 0), P = (4/3, 2/3), u⁺ = (−1/3, 2/3, 2/3).
// Sequential: ball 1 hits ball 2 (P = 1: (0, 1, 0)), ball 2 hits ball 3 (P = 1: (0, 0, 1)).
BOOST_AUTO_TEST_CASE(newtons_cradle_simultaneous_and_sequential) {
  const Mat<double> M = Mat<double>::Identity(3, 3);
  Mat<double> W(2, 3);
  W << -1.0, 1.0, 0.0, 0.0, -1.0, 1.0;
  Vec<double> u(3), e(2);
  u << 1.0, 0.0, 0.0;
  e << 1.0, 1.0;
  const rt::ImpactResult<double> sim = rt::newton_impact<double>(M, W, e, u);
  BOOST_TEST(std::abs(sim.u_plus[0] + 1.0 / 3.0) <= 4 * eps);
  BOOST_TEST(std::abs(sim.u_plus[1] - 2.0 / 3.0) <= 4 * eps);
  BOOST_TEST(std::abs(sim.u_plus[2] - 2.0 / 3.0) <= 4 * eps);
  BOOST_TEST(std::abs(sim.P[0] - 4.0 / 3.0) <= 4 * eps);
  BOOST_TEST(std::abs(sim.P[1] - 2.0 / 3.0) <= 4 * eps);
  BOOST_TEST(std::abs(sim.kinetic_energy_after - 0.5) <= 4 * eps);  // e = 1 conserves T
  BOOST_TEST(std::abs(sim.carnot_prediction) == 0.0);
  // Momentum is conserved by both laws (the gaps are internal).
  BOOST_TEST(std::abs(sim.u_plus.sum() - 1.0) <= 4 * eps);

  const rt::ImpactResult<double> seq = rt::sequential_impacts<double>(M, W, e, u);
  BOOST_TEST(seq.impacts == 2);
  BOOST_TEST(seq.u_plus[0] == 0.0);
  BOOST_TEST(seq.u_plus[1] == 0.0);
  BOOST_TEST(seq.u_plus[2] == 1.0);
  BOOST_TEST(seq.P[0] == 1.0);
  BOOST_TEST(seq.P[1] == 1.0);
  BOOST_TEST(seq.kinetic_energy_after == 0.5);
  BOOST_TEST((seq.status == rt::LcpStatus::solved));

  // e = 0 sequentially: ball 1 and 2 move on together at 1/2, then 2 hits 3 ... the chain
  // converges to the common velocity 1/3 (plastic) only in the limit of infinitely many impacts;
  // the rounding-level stop ends it, with all three at 1/3 to rounding.
  e.setZero();
  const rt::ImpactResult<double> plastic = rt::sequential_impacts<double>(M, W, e, u);
  BOOST_TEST((plastic.status == rt::LcpStatus::solved));
  for (int i = 0; i < 3; ++i) BOOST_TEST(std::abs(plastic.u_plus[i] - 1.0 / 3.0) <= 1e-13);
  const rt::ImpactResult<double> plastic_sim = rt::newton_impact<double>(M, W, e, u);
  for (int i = 0; i < 3; ++i) BOOST_TEST(std::abs(plastic_sim.u_plus[i] - 1.0 / 3.0) <= 4 * eps);
  BOOST_TEST_MESSAGE("plastic cradle, sequential: " << plastic.impacts << " impacts");
}

// Ball of mass 2 at v⁻ = −3 on the floor, e = 0.7: P = −(1 + e) m v⁻ = 10.2, v⁺ = 2.1, T⁺ = e² T⁻.
BOOST_AUTO_TEST_CASE(bouncing_ball) {
  Mat<double> M(1, 1), W(1, 1);
  M << 2.0;
  W << 1.0;
  Vec<double> u(1), e(1);
  u << -3.0;
  e << 0.7;
  const rt::ImpactResult<double> r = rt::newton_impact<double>(M, W, e, u);
  BOOST_TEST(std::abs(r.P[0] - 10.2) <= 4 * eps * 10.2);
  BOOST_TEST(std::abs(r.u_plus[0] - 2.1) <= 4 * eps * 2.1);
  BOOST_TEST(std::abs(r.kinetic_energy_after - 0.49 * r.kinetic_energy_before) <= 8 * eps * 9.0);
  BOOST_TEST(std::abs(r.kinetic_energy_after - r.kinetic_energy_before - r.carnot_prediction) <= 8 * eps * 9.0);
  // Leaving the floor: no impulse.
  u << 1.0;
  const rt::ImpactResult<double> away = rt::newton_impact<double>(M, W, e, u);
  BOOST_TEST(away.P[0] == 0.0);
  BOOST_TEST(away.u_plus[0] == 1.0);
}

namespace {

// Random SPD M (n), m < n independent rows W, common e: the law (P ≥ 0, ḟ⁺ + e ḟ⁻ ≥ 0, complementary),
// T⁺ ≤ T⁻ and Carnot's balance, to rounding scaled by the data.
template <class S>
void random_impacts(unsigned seed, S tolerance) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(-1.0, 1.0);
  const auto rnd = [&](Eigen::Index r, Eigen::Index c) {
    Mat<S> A(r, c);
    for (Eigen::Index i = 0; i < r; ++i)
      for (Eigen::Index j = 0; j < c; ++j) A(i, j) = S(u01(rng));
    return A;
  };
  int separated = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Index n = 3 + trial % 6, m = 1 + trial % (n - 1);
    const Mat<S> B = rnd(n, n);
    const Mat<S> M = B * B.transpose() + S(0.2) * Mat<S>::Identity(n, n);
    const Mat<S> W = rnd(m, n);
    const Vec<S> u = rnd(n, 1);
    const Vec<S> e = Vec<S>::Constant(m, S(0.5) + S(0.5) * S(u01(rng)));
    const rt::ImpactResult<S> r = rt::newton_impact<S>(M, W, e, u);
    BOOST_TEST_REQUIRE((r.status == rt::LcpStatus::solved));
    const Vec<S> fm = W * u, fp = W * r.u_plus;
    const S scale = S(1) + r.P.cwiseAbs().maxCoeff() + fm.cwiseAbs().maxCoeff();
    for (Eigen::Index a = 0; a < m; ++a) {
      const S gap = fp[a] + e[a] * fm[a];
      BOOST_TEST(r.P[a] >= S(0));
      BOOST_TEST(gap >= -tolerance * scale);
      BOOST_TEST(std::abs(r.P[a] * gap) <= tolerance * scale * scale);
      if (r.P[a] == S(0) && fm[a] < S(0)) ++separated;
    }
    const S dT = r.kinetic_energy_after - r.kinetic_energy_before;
    BOOST_TEST(dT <= tolerance * scale * scale);
    BOOST_TEST(std::abs(dT - r.carnot_prediction) <= tolerance * scale * scale);
  }
  BOOST_TEST(separated > 10);  // contacts approaching yet unloaded: the LCP at work
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_multi_contact_double) { random_impacts<double>(1, 1e-12); }
BOOST_AUTO_TEST_CASE(random_multi_contact_long_double) { random_impacts<long double>(2, 1e-15L); }
