#pragma once

// The variational equations of a kernel's ẋ = f(t, x): along a solution x(t),
//     Φ̇ = J(t, x) Φ,   J = ∂f/∂x,   Φ(t0) = I,
// so that a perturbation of the initial state propagates as δx(t) = Φ(t) δx(t0) to first order
// (E. Hairer, S.P. Nørsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.,
// Springer 1993, Sect. I.14, the variational equation). For a linear system ẋ = A x, Φ(t) = e^{At}.
//
// The rates of the joint state y = (x, Φ) ride on the kernel's own rhs() and symbolic jacobian(),
// so a kernel generated with --variational needs no derivation of its own: its variational_rhs()
// only calls the function here.

#include <array>
#include <cstddef>
#include <vector>

#include "eomc/runtime/kernel.hpp"

namespace eomc::runtime {

// y = (x, Φ) with Φ row-major n_state × n_state: n_state + n_state² values, and as many rates.
template <class K>
inline constexpr int n_variational = K::n_state + K::n_state * K::n_state;

template <class K, class S>
  requires KernelWithJacobian<K, S>
void variational_rhs(S t, const S* y, S* dydt, const typename K::Parameters& p) {
  constexpr int n = K::n_state;
  K::rhs(t, y, dydt, p);
  // Past 4096 entries a 16-byte scalar (float128) makes J too large for a thread's stack.
  auto J = [] {
    if constexpr (n * n <= 4096) return std::array<S, std::size_t(n) * n>{};
    else return std::vector<S>(std::size_t(n) * n);
  }();
  K::jacobian(t, y, J.data(), p);
  const S* Phi = y + n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      S sum = S(0);
      for (int k = 0; k < n; ++k) sum += J[i * n + k] * Phi[k * n + j];
      dydt[n + i * n + j] = sum;
    }
}

}  // namespace eomc::runtime
