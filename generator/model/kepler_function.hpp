// The one function the generator itself puts into expressions: the eccentric anomaly
// E = kepler_E(M, e), the root of Kepler's equation E − e sin E = M (0 ≤ e < 1).
//
// The element formulations of an orbit scene (lagrange, gauss, delaunay, the reference orbit
// of encke) write the Cartesian state, and so the disturbing function, in the elements
// through E. Its partials follow from the equation itself,
//     ∂E/∂M = 1/(1 − e cos E),   ∂E/∂e = sin E/(1 − e cos E),
// so R(a, e, i, Ω, ω, M) differentiates symbolically like any other expression. Numerically
// (probes, evalf) and in the emitted kernels it is the runtime's solver,
// eomc::runtime::eccentric_from_mean (runtime/include/eomc/runtime/orbit/kepler.hpp).
#pragma once

#include <ginac/ginac.h>

namespace eomc::model {

DECLARE_FUNCTION_2P(kepler_E)

inline constexpr const char* kepler_E_name = "kepler_E";
// The C++ the emitter writes for kepler_E(M, e), and the header it needs.
inline constexpr const char* kepler_E_cpp = "eomc::runtime::eccentric_from_mean";
inline constexpr const char* kepler_E_header = "eomc/runtime/orbit/kepler.hpp";

// ∂E/∂M and ∂E/∂e at E = kepler_E(M, e), as expressions in E.
GiNaC::ex kepler_E_partial_M(const GiNaC::ex& E, const GiNaC::ex& e);
GiNaC::ex kepler_E_partial_e(const GiNaC::ex& E, const GiNaC::ex& e);

// Whether `e` contains kepler_E anywhere.
bool has_kepler_E(const GiNaC::ex& e);

// E for numbers (double precision): the runtime's solver. Throws std::domain_error outside
// 0 ≤ e < 1 or for a non-finite M.
double kepler_E_value(double M, double e);

}  // namespace eomc::model
