#pragma once

// Rectification of Encke's method (R.H. Battin, An Introduction to the Mathematics and Methods
// of Astrodynamics, rev. ed., AIAA 1999, §9.3). The integrated state holds the deviation
// δ = r − ρ of the orbit from a reference Kepler ellipse ρ(t), whose epoch and classical
// elements ride in the state as constants. δ grows with the perturbation, and with it the
// truncation error of the δ equations; once |δ| > ratio |ρ| the reference becomes the
// osculating ellipse of the total state r = ρ + δ at t (epoch t) and δ is re-expressed in it,
// so that r and ṙ go on unchanged up to rounding and δ starts again from (nearly) zero.
//
// A total state that is no ellipse (specific energy ≥ 0) keeps the old reference: the δ
// equations hold for any δ; only an ellipse can be written through Kepler's equation.

#include <array>
#include <cmath>
#include <cstddef>

#include "eomc/runtime/orbit/orbital_elements.hpp"

namespace eomc::runtime {

// Where an Encke state keeps its parts.
struct EnckeLayout {
  std::size_t deviation;  // δ (3) then δ̇ (3)
  std::size_t elements;   // the reference's epoch t_ref, then a, e, i, Ω, ω and M at t_ref (7)
  std::size_t count;      // the number of rectifications so far
};

// Rectifies x in place at time t when |δ| > ratio |ρ| and the total state is an ellipse;
// returns whether it did. reference(t, x, out) writes the reference orbit the state x describes
// at t: out = (ρ (3), ρ̇ (3), μ).
template <class S, class Reference>
bool encke_rectify(S t, S* x, const EnckeLayout& at, double ratio, Reference&& reference) {
  using std::sqrt;
  const std::size_t D = at.deviation, E = at.elements;
  std::array<S, 7> ref;
  reference(t, static_cast<const S*>(x), ref.data());
  const S d2 = x[D] * x[D] + x[D + 1] * x[D + 1] + x[D + 2] * x[D + 2];
  const S rho2 = ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2];
  if (!(d2 > S(ratio * ratio) * rho2)) return false;
  CartesianState<S> total;
  for (std::size_t k = 0; k < 6; ++k) total[k] = ref[k] + x[D + k];
  const S r = sqrt(total[0] * total[0] + total[1] * total[1] + total[2] * total[2]);
  const S v2 = total[3] * total[3] + total[4] * total[4] + total[5] * total[5];
  if (!(v2 / S(2) - ref[6] / r < S(0))) return false;
  const ClassicalElements<S> el = classical_from_cartesian(total, ref[6]);
  x[E] = t;
  x[E + 1] = el.a;
  x[E + 2] = el.e;
  x[E + 3] = el.i;
  x[E + 4] = el.raan;
  x[E + 5] = el.argp;
  x[E + 6] = el.mean_anomaly;
  reference(t, static_cast<const S*>(x), ref.data());
  for (std::size_t k = 0; k < 6; ++k) x[D + k] = total[k] - ref[k];
  x[at.count] += S(1);
  return true;
}

}  // namespace eomc::runtime
