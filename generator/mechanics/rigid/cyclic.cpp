#include "mechanics/rigid/cyclic.hpp"

#include <algorithm>

#include "mechanics/invariants.hpp"
#include "mechanics/kinematics/operators.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;
using symbolic::derivative;

std::string momentum_name(const std::string& coordinate) { return "momentum_" + coordinate; }

std::vector<CyclicCoordinate> cyclic_coordinates(const model::Model& model, const Equations& eqs) {
    std::vector<CyclicCoordinate> out;
    // A free carrier's quasi-velocities have no Lagrangian momenta of their own here, and the
    // prover (proven_constant) works on coordinates alone.
    if (!model.lagrangian_in_coordinates() || !model.quasi_velocities.empty()) return out;
    const std::size_t n = model.coordinates.size();
    if (eqs.equations.size() != n || model.generalized_forces.size() != n) return out;
    const ex L = eqs.T - eqs.V;
    for (std::size_t c = 0; c < n; ++c) {
        const auto& coordinate = model.coordinates[c];
        if (L.has(coordinate.q) || !model.generalized_forces[c].is_zero()) continue;
        if (std::any_of(model.generalized_forces.begin(), model.generalized_forces.end(),
                        [&](const ex& Q) { return Q.has(coordinate.q); }))
            continue;
        // A reaction Σ λ_α W_αc in the equation of q_c would change its momentum.
        if (std::any_of(eqs.constraints.begin(), eqs.constraints.end(),
                        [&](const ConstraintRow& row) { return c < row.W.size() && !row.W[c].is_zero(); }))
            continue;
        // An impulse P W_αc at an impact of a unilateral row would change it too (Mei, §6.5).
        if (std::any_of(eqs.unilateral.begin(), eqs.unilateral.end(),
                        [&](const UnilateralRow& u) { return c < u.row.W.size() && !u.row.W[c].is_zero(); }))
            continue;
        CyclicCoordinate cyclic;
        cyclic.coordinate = coordinate.name;
        cyclic.index = c;
        cyclic.momentum = eqs.equations[c].dT_dqdot - derivative(eqs.V, coordinate.q_dot);
        if (cyclic.momentum.is_zero()) continue;  // q_c carries no mass: nothing to conserve
        cyclic.proven = proven_constant(model, eqs, cyclic.momentum);
        out.push_back(std::move(cyclic));
    }
    return out;
}

void add_cyclic_momenta(const model::Model& model, Equations& eqs) {
    for (const auto& c : cyclic_coordinates(model, eqs)) {
        if (!c.proven) continue;
        const std::string name = momentum_name(c.coordinate);
        const bool taken =
            std::any_of(model.coordinates.begin(), model.coordinates.end(),
                        [&](const model::Coordinate& q) { return q.name == name || q.name + "_dot" == name; }) ||
            std::any_of(eqs.invariants.begin(), eqs.invariants.end(), [&](const Invariant& i) { return i.name == name; });
        if (taken) continue;
        eqs.invariants.push_back(
            {name, c.momentum,
             "p_" + c.coordinate + " = ∂L/∂" + c.coordinate +
                 "_dot: the coordinate is cyclic (absent from L and the forces), so its momentum is conserved "
                 "(Noether; proven along the equations)"});
    }
}

RouthReduction routh_reduction(const model::Model& model, const Equations& eqs,
                               const std::vector<CyclicCoordinate>& all) {
    RouthReduction r;
    for (const auto& c : all)
        if (c.proven) r.cyclic.push_back(c);
    if (r.cyclic.empty()) {
        r.reason = "no cyclic coordinate";
        return r;
    }
    const std::size_t n = model.coordinates.size();
    if (r.cyclic.size() == n) {
        r.reason = "every coordinate is cyclic: the momenta alone give the motion, q̇ = const";
        return r;
    }
    GiNaC::lst equations, unknowns;
    for (const auto& c : r.cyclic) {
        r.beta.push_back(GiNaC::symbol("beta_" + c.coordinate, "\\beta_{" + c.coordinate + "}"));
        unknowns.append(model.coordinates[c.index].q_dot);
    }
    for (std::size_t k = 0; k < r.cyclic.size(); ++k) {
        const ex& p = r.cyclic[k].momentum;
        // p_c must be linear in the cyclic velocities for β_c = p_c to be solved here.
        for (const auto& u : unknowns)
            for (const auto& v : unknowns)
                if (!derivative(derivative(p, GiNaC::ex_to<GiNaC::symbol>(u)), GiNaC::ex_to<GiNaC::symbol>(v)).is_zero()) {
                    r.reason = "a cyclic momentum is not linear in the cyclic velocities";
                    return r;
                }
        equations.append(p == r.beta[k]);
    }
    ex solution;
    try {
        solution = GiNaC::lsolve(equations, unknowns);
    } catch (const std::exception& e) {
        r.reason = std::string("p_c = β_c could not be solved for the cyclic velocities: ") + e.what();
        return r;
    }
    if (solution.nops() != r.cyclic.size()) {
        r.reason = "p_c = β_c does not determine the cyclic velocities";
        return r;
    }
    GiNaC::exmap velocities;
    for (std::size_t k = 0; k < solution.nops(); ++k) {
        const ex v = symbolic::simplified(solution.op(k).rhs());
        velocities[solution.op(k).lhs()] = v;
        r.velocities.push_back(v);
    }
    ex R = eqs.T - eqs.V;
    for (std::size_t k = 0; k < r.cyclic.size(); ++k) R -= r.beta[k] * model.coordinates[r.cyclic[k].index].q_dot;
    r.routhian = symbolic::simplified(R.subs(velocities));
    for (std::size_t s = 0; s < n; ++s) {
        if (std::any_of(r.cyclic.begin(), r.cyclic.end(), [&](const CyclicCoordinate& c) { return c.index == s; }))
            continue;
        r.equations.push_back({model.coordinates[s].name, symbolic::simplified(euler_operator(model, r.routhian, s)),
                               model.generalized_forces[s]});
    }
    r.done = true;
    return r;
}

}  // namespace eomc::mechanics::rigid
