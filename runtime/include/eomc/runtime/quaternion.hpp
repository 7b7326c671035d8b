#pragma once

// A unit quaternion e = (e0, e1, e2, e3) carried in a state (a rigid body's attitude). Its
// kinematic rates ė = ½ e ⊗ ω keep |e| = 1 exactly, an integrator only to its error; the rotation
// R(e)/|e|² is orthogonal for any |e| ≠ 0, so dividing by |e| changes no attitude and only keeps e
// well scaled (J. Wittenburg, Dynamics of Multibody Systems, 2nd ed., Springer 2008, ch. 2,
// Euler parameters).

#include <cmath>
#include <cstddef>

namespace eomc::runtime {

// Puts e[0..4) back on |e| = 1.
template <class S>
void renormalise_quaternion(S* e) {
  using std::sqrt;
  const S norm = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
  for (int i = 0; i < 4; ++i) e[i] /= norm;
}

}  // namespace eomc::runtime
