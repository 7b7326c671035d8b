// What the classical and Delaunay element formulations share (gauss.cpp, lagrange_planetary.cpp,
// delaunay.cpp, mean.cpp; Mei, ch. 2): the initial osculating elements of the model's initial
// state, the state's symbols and the conic they describe, the model's Cartesian expressions
// written on that conic, the perturbing acceleration in radial, transverse and normal axes,
// Gauss's and Lagrange's planetary equations, and the form's common tail (state, outputs,
// events). Internal to mechanics/orbit.
#pragma once

#include <array>

#include <ginac/ginac.h>

#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "mechanics/orbit/conic.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::elements {

// The classical elements' names as the kernel's state names them.
inline constexpr std::array<const char*, 6> classical_names{"a", "e", "i", "raan", "argp", "mean_anomaly"};
inline constexpr std::array<const char*, 6> delaunay_names{"l", "g", "h", "L", "G", "H"};

// An element formulation's starting point: its state symbols, the classical elements as
// expressions of them, and the conic those describe.
struct Setting {
    const model::Model& model;
    runtime::ClassicalElements<double> initial;  // the initial osculating elements (μ at its default)
    std::array<GiNaC::symbol, 6> q;              // the state, in kernel order
    GiNaC::ex a, e, i, ci, si;                   // i only for the classical state (Delaunay: cos i = H/G)
    Conic conic;
    Vec nonconservative;                         // the non-conservative acceleration on the conic, inertial axes
    bool has_nonconservative = false;

    // A Cartesian expression of the model (x, y, z, their rates, r) written on the conic.
    GiNaC::ex on_conic(const GiNaC::ex& value) const;
};

// The state (a, e, i, Ω, ω, M) or, with `delaunay`, (l, g, h, L, G, H). Throws InputError at the
// formulation when the initial orbit has no elliptic elements.
Setting classical_setting(const model::Model& model);
Setting delaunay_setting(const model::Model& model);

// The perturbing acceleration (Cartesian, inertial) in radial, transverse and normal components.
Vec rtn(const Vec& a, const Conic& k);

// Gauss's equations (Vallado, Fundamentals of Astrodynamics and Applications, 4th ed., eq. 9-24;
// Mei, ch. 2) for the force F = (F_r, F_t, F_n) per unit mass: the rates of (a, e, i, Ω, ω, M)
// less the Kepler motion n of M.
std::array<GiNaC::ex, 6> gauss_rates(const Conic& k, const Vec& F);

// Lagrange's planetary equations (Brouwer & Clemence, Methods of Celestial Mechanics, 1961,
// ch. XI; Vallado eq. 9-12) from the partials of R in (a, e, i, Ω, ω, M).
std::array<GiNaC::ex, 6> lagrange_rates(const GiNaC::ex& n, const GiNaC::ex& a, const GiNaC::ex& e,
                                        const GiNaC::ex& i, const std::array<GiNaC::ex, 6>& R);

// Lagrange's planetary equations in the partials of R (in the classical state), with Gauss's terms
// for the non-conservative acceleration; R and its partials go to the derivation, R named `shown_name`.
std::array<GiNaC::ex, 6> planetary_equations(const Setting& s, const GiNaC::ex& R, const char* shown_name,
                                             FirstOrderForm& form);

// The form's state, rates and Cartesian outputs, and the scene's events written on the conic.
void complete(const Setting& s, const std::array<double, 6>& initial, const std::array<GiNaC::ex, 6>& rates,
              FirstOrderForm& form);

// The Cowell equations' invariants (proven in Cartesian variables, so valid in any) written on the conic.
void carry_invariants(const Setting& s, const Equations& cowell, FirstOrderForm& form);

}  // namespace eomc::mechanics::elements
