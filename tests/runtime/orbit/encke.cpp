// runtime/orbit/encke.hpp: Encke's rectification (Battin §9.3). On a state laid out as the encke
// formulation's (δ, δ̇; the reference's epoch and elements; a count), with the reference ellipse
// computed from those elements by the runtime's own conversion:
//   * below the threshold, or for a total state that is no ellipse, nothing changes;
//   * above it, the total state ρ + δ is the same before and after, the new δ is zero to the
//     round-off of the elements' round trip, the epoch is t and the count goes up by one;
//   * right after a rectification the state is far below the threshold (no second one).
#define BOOST_TEST_MODULE runtime_encke
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>

#include "eomc/runtime/orbit/encke.hpp"
#include "eomc/runtime/orbit/orbital_elements.hpp"

namespace {

namespace rt = eomc::runtime;
const double eps = std::numeric_limits<double>::epsilon();
const double mu = 398600.4418;  // km³/s², the Earth's
constexpr rt::EnckeLayout layout{0, 6, 13};
constexpr double ratio = 1e-2;
using State = std::array<double, 14>;

// ρ, ρ̇ of the reference the state holds, at t (its mean anomaly advanced by n (t − t_ref)), then μ.
void reference(double t, const double* x, double* out) {
  const double a = x[7], n = std::sqrt(mu / (a * a * a));
  const rt::ClassicalElements<double> el{a, x[8], x[9], x[10], x[11], x[12] + n * (t - x[6])};
  const rt::CartesianState<double> c = rt::cartesian_from_classical(el, mu);
  for (int k = 0; k < 6; ++k) out[k] = c[k];
  out[6] = mu;
}

// An inclined, eccentric reference (epoch 100 s) and a deviation of `scale` times |ρ| and |ρ̇|
// at t, spread over all components.
State encke_state(double t, double scale, double velocity_scale) {
  State x{};
  x[6] = 100.0;
  x[7] = 8000.0, x[8] = 0.2, x[9] = 0.9, x[10] = 0.4, x[11] = 1.1, x[12] = 0.3;
  x[13] = 2.0;
  std::array<double, 7> rho{};
  reference(t, x.data(), rho.data());
  const double r = std::hypot(rho[0], rho[1], rho[2]), v = std::hypot(rho[3], rho[4], rho[5]);
  const std::array<double, 6> direction{0.6, -0.48, 0.64, -0.36, 0.8, 0.48};  // two unit vectors
  for (int k = 0; k < 3; ++k) x[k] = scale * r * direction[k];
  for (int k = 3; k < 6; ++k) x[k] = velocity_scale * v * direction[k];
  return x;
}

}  // namespace

BOOST_AUTO_TEST_CASE(below_the_threshold_nothing_changes) {
  const double t = 1234.5;
  const State before = encke_state(t, 0.5 * ratio, 0.5 * ratio);
  State x = before;
  BOOST_TEST(!rt::encke_rectify(t, x.data(), layout, ratio, reference));
  for (std::size_t k = 0; k < x.size(); ++k) BOOST_TEST(x[k] == before[k]);
}

BOOST_AUTO_TEST_CASE(an_unbound_total_state_keeps_its_reference) {
  const double t = 1234.5;
  State before = encke_state(t, 2 * ratio, 0.0);
  std::array<double, 7> rho{};
  reference(t, before.data(), rho.data());
  // δ̇ = ρ̇: ṙ = 2 ρ̇, so v²/2 − μ/r = 2μ(2/r − 1/a) − μ/r = μ(3/r − 2/a) (vis-viva), positive
  // for any r < 1.5 a, as on this e = 0.2 orbit (r ≤ 1.2 a) even with δ in r.
  for (int k = 3; k < 6; ++k) before[k] = rho[k];
  double r2 = 0, v2 = 0;
  for (int k = 0; k < 3; ++k) r2 += (rho[k] + before[k]) * (rho[k] + before[k]);
  for (int k = 3; k < 6; ++k) v2 += (rho[k] + before[k]) * (rho[k] + before[k]);
  BOOST_REQUIRE(v2 / 2 - mu / std::sqrt(r2) > 0);
  State x = before;
  BOOST_TEST(!rt::encke_rectify(t, x.data(), layout, ratio, reference));
  for (std::size_t k = 0; k < x.size(); ++k) BOOST_TEST(x[k] == before[k]);
}

// The total state: ρ_new + δ_new = total holds to the one rounding of δ_new = total − ρ_new
// (half an ulp of δ_new). δ_new itself is the round trip Cartesian → elements → Cartesian of the
// total state, a few tens of roundings each amplified by at most (1 + e)/(1 − e) = 1.5 near
// pericentre: within 64 eps of |r| and |ṙ|.
BOOST_AUTO_TEST_CASE(rectification_keeps_the_total_state_and_zeroes_the_deviation) {
  for (double t : {100.0, 1234.5, 5000.0, 20000.0}) {
    State x = encke_state(t, 3 * ratio, 2 * ratio);
    std::array<double, 7> rho{};
    reference(t, x.data(), rho.data());
    std::array<double, 6> total{};
    for (int k = 0; k < 6; ++k) total[k] = rho[k] + x[k];

    BOOST_TEST(rt::encke_rectify(t, x.data(), layout, ratio, reference));
    BOOST_TEST(x[6] == t);
    BOOST_TEST(x[13] == 3.0);
    std::array<double, 7> rho_new{};
    reference(t, x.data(), rho_new.data());
    const double r = std::hypot(total[0], total[1], total[2]), v = std::hypot(total[3], total[4], total[5]);
    double worst_sum = 0, worst_delta_r = 0, worst_delta_v = 0;
    for (int k = 0; k < 6; ++k) {
      const long double sum = static_cast<long double>(rho_new[k]) + x[k];
      BOOST_TEST(std::abs(static_cast<double>(sum - total[k])) <= 0.5 * eps * std::abs(x[k]), "component " << k);
      worst_sum = std::max(worst_sum, std::abs(static_cast<double>(sum - total[k])));
      (k < 3 ? worst_delta_r : worst_delta_v) = std::max(k < 3 ? worst_delta_r : worst_delta_v, std::abs(x[k]));
    }
    BOOST_TEST_MESSAGE("t = " << t << ": |rho + delta - total| <= " << worst_sum << ", new |delta| <= "
                              << worst_delta_r / (eps * r) << " eps |r|, |delta_dot| <= " << worst_delta_v / (eps * v)
                              << " eps |v|");
    BOOST_TEST(worst_delta_r <= 64 * eps * r);
    BOOST_TEST(worst_delta_v <= 64 * eps * v);

    // Far below the threshold now: a second call changes nothing.
    const State after = x;
    BOOST_TEST(!rt::encke_rectify(t, x.data(), layout, ratio, reference));
    for (std::size_t k = 0; k < x.size(); ++k) BOOST_TEST(x[k] == after[k]);
  }
}
