// A programmed motion as rows of the controlled equations (Mei, ch. 3; Galiullin, Inverse
// Problems of Dynamics, 1981; Erugin, PMM 16, 1952): each program ω(q, t) = 0 or φ(q, q̇, t) = 0
// reaches the acceleration level through the shared row builder (mechanics/constraints), as
//     ω̈ = Ā q̈ + a   or   φ̇ = Ā q̈ + b,
// and the controlled system is
//     M q̈ = f + D λ,   Ā q̈ = c,   c = −a − 2α ω̇ − β² ω  (or −b − κ φ; −a, −b open loop),
// whose residual then follows Erugin's law ω̈ + 2α ω̇ + β² ω = 0 (φ̇ + κ φ = 0).
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/constraints/rows.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

struct ProgramRow {
    ConstraintRow row;            // position ω (configuration programs; 0 otherwise), velocity ω̇ or φ, W = Ā's row, bias a or b
    bool configuration = true;
    bool closed_loop = false;
    double alpha = 0.0, beta = 0.0, kappa = 0.0;
    GiNaC::ex target;             // c: Ā q̈ = c along the controlled motion
    model::ProgramControl control = model::ProgramControl::ideal;
    // The columns of D this program brings, each over the velocities (ideal: Āᵀ's column, the row W
    // itself; directions: the given one; actuated: unit columns), and their multipliers' names.
    std::vector<std::vector<GiNaC::ex>> columns;
    std::vector<std::string> column_names;  // lambda_<program> (one column) or lambda_<program>_<coordinate>
    SourcePos pos, control_pos;

    const std::string& name() const { return row.name; }
    // The residual the law is stated in: ω, or φ.
    const GiNaC::ex& residual() const { return configuration ? row.position : row.velocity; }
};

}  // namespace eomc::mechanics
