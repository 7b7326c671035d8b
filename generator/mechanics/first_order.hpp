// The equations as a kernel integrates them: a first-order system ẋ = F(t, x).
//
// Every formulation ends here. Some state components have their rate in closed form (the
// coordinates, q̇ = q_dot; a quaternion, ½ q ⊗ ω; Hamilton's q̇ = ∂H/∂p); the rest, the
// velocity block u (q̇ and a free carrier's quasi-velocities; Hamilton's p), is solved from
// M(t, x) u̇ = f(t, x). Lowering and emission work on this form only, so a new formulation
// needs no new code generator.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "mechanics/unilateral/rows.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

struct StateComponent {
    std::string name;
    GiNaC::symbol symbol;
    double initial = 0.0;
};

struct NamedExpression {
    std::string name;
    GiNaC::ex value;
};

// g(t, x) of a scene event, in the form's state (Hamilton's: q̇ replaced by ∂H/∂p).
struct EventFunction {
    std::string name;
    GiNaC::ex value;
    int direction = 0;  // +1 upwards only, -1 downwards only, 0 both
    bool terminal = false;
};

// Encke's rectification (mechanics/orbit/encke.hpp): after an accepted step the kernel's project()
// resets the reference orbit to the osculating orbit of the total state when the deviation has
// grown past `ratio` of the reference radius, and re-expresses the deviation in the new reference.
struct Rectification {
    double ratio = 0.0;          // rectify when |δ| > ratio |ρ|
    std::size_t deviation = 0;   // δ, δ̇: state[deviation .. deviation + 6)
    std::size_t elements = 0;    // epoch t_ref, then a, e, i, Ω, ω, M at t_ref: state[elements .. elements + 7)
    std::size_t count = 0;       // the state index counting the rectifications
    // ρ, ρ̇ (functions of t and the reference elements), then μ: the kernel computes the
    // osculating elements with this μ and the new deviation with this ρ.
    std::vector<GiNaC::ex> reference;
};

struct FirstOrderForm {
    std::string description;  // one line for the kernel's banner: what the state and equations are
    std::vector<StateComponent> state;
    std::size_t n_coordinates = 0;  // the leading entries are the generalized coordinates

    // x[velocity_offset .. velocity_offset + n_velocities) solved from M u̇ = f; M and f are
    // functions of (t, x), u̇ is named by velocity_rates (the symbols q_ddot, v0_dot, …).
    std::size_t velocity_offset = 0;
    std::vector<StateComponent> velocity_rates;
    GiNaC::matrix mass_matrix;
    std::vector<GiNaC::ex> forcing;

    // (state index, rate) for every component outside the velocity block, in state order.
    std::vector<std::pair<std::size_t, GiNaC::ex>> explicit_rates;

    std::vector<Invariant> invariants;
    // Where M is singular (Equations::singular_sets): the kernel's singular_sets() indicators.
    std::vector<SingularSet> singular_sets;
    // Quantities written beside the state (a free carrier's reactions): functions of (t, x, u̇).
    std::vector<NamedExpression> outputs;

    std::vector<EventFunction> events;

    // A Newtonian scene's Santilli conditions S1–S5 as residuals (empty otherwise): the kernel
    // carries them so that a simulation can watch them along its trajectory.
    std::vector<NamedExpression> santilli_residuals;

    // q̈ = a(t, q) alone, M constant: the symplectic splitting methods apply.
    bool separable = false;
    // First state index of each unit quaternion (a free carrier's attitude): the kernel's
    // project() puts it back on |e| = 1 after every step.
    std::vector<std::size_t> unit_quaternions;
    // First state index of each unit 3-vector (Poisson's vertical γ): project() normalises it.
    std::vector<std::size_t> unit_vectors;
    // Bilateral constraint rows on the velocity block (mechanics/constraints/rows.hpp): the kernel
    // solves M u̇ − Wᵀλ = f, W u̇ = −bias (− stabilisation), outputs λ, and its project() puts the
    // state back on the rows that ask for projection.
    std::vector<ConstraintRow> constraints;
    // Unilateral rows (mechanics/unilateral/rows.hpp): the kernel writes their gaps, W and bias and
    // restitutions; the host integrates through impacts, contact phases and separations.
    std::vector<UnilateralRow> unilateral;
    // Programs and their controls (mechanics/control/rows.hpp): the kernel solves M u̇ = f + D λ,
    // Ā u̇ = c at run time and outputs the residuals, λ and Q_c = D λ.
    std::vector<ProgramRow> programs;
    bool redundant_programs = false;
    // The encke formulation's reference orbit, reset by project() (absent for every other form).
    std::optional<Rectification> rectification;

    // What a formulation derived on the way, "name = value" in order, for `eomc derive` (an orbit's
    // disturbing function in the elements, its partials, the equations in named partials).
    std::vector<NamedExpression> derivation;

    std::size_t n_velocities() const { return velocity_rates.size(); }
};

// The first-order system the kernel integrates: Lagrange's equations as lagrange_form writes
// them, or for an orbit scene its formulation's (mechanics/orbit/formulation.hpp).
FirstOrderForm first_order_form(const model::Model& model, const Equations& equations);

// Lagrange's equations (with a free carrier's quasi-velocities and kinematics, when there is one)
// as the first-order system x = (q, u, kinematic states); an orbit's cowell formulation.
FirstOrderForm lagrange_form(const model::Model& model, const Equations& equations);

}  // namespace eomc::mechanics
