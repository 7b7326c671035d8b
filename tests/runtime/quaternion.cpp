// runtime/quaternion.hpp: renormalising a unit quaternion carried in a state. Its result has
// |e| = 1 to the rounding of the computation, a unit quaternion is left as it is, and the bundled
// free_disk_tube_ball kernel, which writes the same renormalisation out in its project(), agrees
// with it bit for bit.
#define BOOST_TEST_MODULE runtime_quaternion
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string_view>

#include "eomc/runtime/quaternion.hpp"
#include "free_disk_tube_ball.hpp"

namespace {

const double eps = std::numeric_limits<double>::epsilon();

// |e| in long double, so that the measurement adds no rounding of double's size.
double norm_of(const double* e) {
  long double s = 0;
  for (int i = 0; i < 4; ++i) s += static_cast<long double>(e[i]) * e[i];
  return static_cast<double>(std::sqrt(s));
}

}  // namespace

// Rounding, with u = eps/2: the sum of four squares carries a relative error of at most 4u,
// the square root halves it and adds u, each division adds u; so | |e'| − 1 | ≤ 4u = 2 eps to
// first order, whatever |e| was.
BOOST_AUTO_TEST_CASE(the_result_has_unit_norm) {
  std::mt19937_64 rng(20240613);
  std::uniform_real_distribution<double> component(-1.0, 1.0), decade(-3.0, 3.0);
  double worst = 0.0;
  for (int n = 0; n < 100000; ++n) {
    std::array<double, 4> e{};
    const double scale = std::pow(10.0, decade(rng));
    for (double& c : e) c = scale * component(rng);
    eomc::runtime::renormalise_quaternion(e.data());
    worst = std::max(worst, std::abs(norm_of(e.data()) - 1.0));
  }
  BOOST_TEST_MESSAGE("| |e| - 1 | after renormalisation: at most " << worst / eps << " eps");
  BOOST_TEST(worst <= 2 * eps);
}

// A quaternion whose norm is exactly 1 in double is left bit for bit; one that is 1 only to
// rounding moves by no more than that rounding (the bound above, per component).
BOOST_AUTO_TEST_CASE(a_unit_quaternion_is_left_unchanged) {
  const std::array<std::array<double, 4>, 4> exact{{{1, 0, 0, 0}, {0, 0, -1, 0}, {0.5, 0.5, 0.5, 0.5}, {0.5, -0.5, 0.5, -0.5}}};
  for (const auto& unit : exact) {
    std::array<double, 4> e = unit;
    eomc::runtime::renormalise_quaternion(e.data());
    for (int i = 0; i < 4; ++i) BOOST_TEST(e[i] == unit[i]);
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> component(-1.0, 1.0);
  double worst = 0.0;
  for (int n = 0; n < 10000; ++n) {
    std::array<double, 4> e{};
    for (double& c : e) c = component(rng);
    eomc::runtime::renormalise_quaternion(e.data());
    std::array<double, 4> again = e;
    eomc::runtime::renormalise_quaternion(again.data());
    for (int i = 0; i < 4; ++i) worst = std::max(worst, std::abs(again[i] - e[i]));
  }
  BOOST_TEST_MESSAGE("a second renormalisation moves a component by at most " << worst / eps << " eps");
  BOOST_TEST(worst <= 2 * eps);
}

// The bundled kernel's project() renormalises its attitude quaternion x[4..8) and touches nothing else.
BOOST_AUTO_TEST_CASE(the_bundled_kernel_renormalises_as_the_runtime_does) {
  using K = eomc::models::FreeDiskTubeBall;
  static_assert(std::string_view(K::state_names[4]) == "carrier_e0" && std::string_view(K::state_names[7]) == "carrier_e3",
                "x[4..8) is the carrier's quaternion");
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  const K::Parameters p{};
  for (int n = 0; n < 1000; ++n) {
    std::array<double, K::n_state> x{};
    for (double& c : x) c = value(rng);
    std::array<double, K::n_state> y = x;
    K::project(0.0, x.data(), p);
    eomc::runtime::renormalise_quaternion(y.data() + 4);
    for (int i = 0; i < K::n_state; ++i) BOOST_TEST(x[i] == y[i]);
  }
}
