// The programmed motions ([[program]]; Mei, ch. 3): each relation, its law and its control, and
// the [[constraint]] rows beside them turned into ideal programs.
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

// [[program]] rows (Mei, ch. 3): the relation parsed in the phase-space symbols, its kind read off
// the symbols it holds, the law checked against the kind (φ̇ + κφ = 0 is first order: a relation
// of the coordinates would need its rate given too; ω̈ + 2αω̇ + β²ω = 0 is second order: a relation
// holding the rates would need their rates), and the control's directions.
void build_programs(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    for (const auto& given : scene.programs) {
        Program row;
        row.name = given.name;
        row.pos = given.constraint.pos;
        row.erugin_pos = given.erugin_pos;
        row.control_pos = given.control_pos;
        row.expression = symbols.parse(given.constraint, phase, fmt::format("the program '{}'", given.name));
        row.configuration = true;
        for (const auto& c : model.coordinates)
            if (row.expression.has(c.q_dot)) row.configuration = false;
        bool moves = false;
        for (const auto& c : model.coordinates) moves = moves || row.expression.has(c.q) || row.expression.has(c.q_dot);
        if (model.rigid) {
            // A rigid body (Mei §3.2): programs on the angular velocity, φ(ω, attitude, t) = 0, or on
            // the attitude alone, ω(γ, e, t) = 0 (configuration space: e the quaternion formulation's
            // attitude, for an error quaternion), realised by torques in Euler's equations, in the
            // formulations whose state holds ω itself.
            const auto kind = model.rigid->formulation;
            if (kind != scene::RigidFormulationKind::euler_poisson && kind != scene::RigidFormulationKind::quaternion)
                throw InputError(row.pos, fmt::format("the program '{}' on a rigid body needs the euler_poisson or "
                                                      "quaternion formulation (the state must hold omega = (p, q, r)), "
                                                      "not {}",
                                                      given.name, scene::name(kind)));
            bool rates = false;
            for (const auto& w : model.rigid->omega) rates = rates || row.expression.has(w);
            for (const auto& g : model.rigid->gamma) moves = moves || row.expression.has(g);
            if (model.rigid->attitude)
                for (const auto& e : *model.rigid->attitude) moves = moves || row.expression.has(e);
            moves = moves || rates;
            row.configuration = !rates;
        }
        if (!moves)
            throw InputError(row.pos, fmt::format("the program '{}' holds no coordinate or rate: a relation of t and the "
                                                  "parameters alone is not a motion a control can realise",
                                                  given.name));
        row.closed_loop = given.closed_loop;
        row.alpha = given.alpha;
        row.beta = given.beta;
        row.kappa = given.kappa;
        if (given.closed_loop && row.configuration && given.phase_law)
            throw InputError(given.erugin_pos,
                             fmt::format("the program '{}' is a relation of the coordinates (configuration space), so "
                                         "Erugin's law is of second order: give erugin = {{ alpha = ..., beta = ... }} "
                                         "(omega_ddot + 2 alpha omega_dot + beta^2 omega = 0), not kappa",
                                         given.name));
        if (given.closed_loop && !row.configuration && !given.phase_law)
            throw InputError(given.erugin_pos,
                             fmt::format("the program '{}' holds rates (phase space), so Erugin's law is of first order: "
                                         "give erugin = {{ kappa = ... }} (phi_dot + kappa phi = 0), not alpha and beta",
                                         given.name));
        if (given.control == "directions") {
            row.control = ProgramControl::directions;
            row.direction.assign(model.coordinates.size(), 0);
            for (const auto& [coordinate, text] : given.directions) {
                std::size_t k = 0;
                while (model.coordinates[k].name != coordinate) ++k;
                row.direction[k] = symbols.parse(
                    text, phase, fmt::format("the control direction of program '{}' on '{}'", given.name, coordinate));
            }
        } else if (given.control == "moment") {
            row.control = ProgramControl::moment;
            for (const auto& m : given.moment)
                row.direction.push_back(symbols.parse(
                    m, unsigned(SymbolKind::parameter),
                    fmt::format("the control moment of program '{}' (body axes; parameters only)", given.name)));
        } else if (given.control == "actuated") {
            row.control = ProgramControl::actuated;
            for (const auto& [coordinate, where] : given.actuated) {
                std::size_t k = 0;
                while (model.coordinates[k].name != coordinate) ++k;
                row.actuated.push_back(k);
            }
        }
        model.programs.push_back(std::move(row));
    }
}

// [[constraint]] rows beside [[program]] rows (Mei ch. 3 with §6.6's rows): a bilateral row is an
// ideal program whose law is its stabilisation — Baumgarte's f̈ + 2αḟ + β²f = 0 is Erugin's law with
// Galiullin's gains, φ̇ + αφ = 0 for a kinematic row, the open loop for "none" — so the reactions μ
// and the controls λ are solved together from M u̇ = f + Wᵀ μ + D λ, W u̇ = c_W, Ā u̇ = c (the
// control chapter's kernel; Udwadia & Kalaba, Analytical Dynamics, 1996, ch. 2, treat constraints
// and programs alike). The rows go first, keeping their names (lambda_<name> is μ). "project" is
// the constrained kernel's own step after each step, which the controlled kernel has not: refused.
void constraints_as_programs(const scene::Scene& scene, Model& model) {
    std::vector<Program> rows;
    for (std::size_t a = 0; a < model.constraints.size(); ++a) {
        const Constraint& c = model.constraints[a];
        const scene::Constraint& given = scene.constraints[a];
        if (c.stabilization == ConstraintStabilization::project)
            throw InputError(given.stabilize_pos,
                             fmt::format("the constraint '{}' beside [[program]] rows is solved with them as one more "
                                         "ideal row, whose law is its stabilisation: give stabilize = {{ alpha = ..., "
                                         "beta = ... }} (Baumgarte's law, realised exactly as Erugin's) or \"none\"; "
                                         "\"project\" (the default) is the constrained kernel's step, which a "
                                         "controlled kernel does not take",
                                         c.name));
        for (const auto& p : model.programs)
            if (p.name == c.name)
                throw InputError(p.pos, fmt::format("the program '{}' has the name of a [[constraint]] row; the two "
                                                    "are solved together and their outputs (lambda_{}) would clash",
                                                    p.name, p.name));
        Program row;
        row.name = c.name;
        row.configuration = c.holonomic;
        row.expression = c.expression;
        row.closed_loop = c.stabilization == ConstraintStabilization::baumgarte;
        row.alpha = c.holonomic ? c.alpha : 0.0;
        row.beta = c.holonomic ? c.beta : 0.0;
        row.kappa = c.holonomic ? 0.0 : c.alpha;
        row.control = ProgramControl::ideal;
        row.pos = row.control_pos = c.pos;
        row.erugin_pos = given.stabilize_pos;
        rows.push_back(std::move(row));
    }
    rows.insert(rows.end(), model.programs.begin(), model.programs.end());
    model.programs = std::move(rows);
    model.constraints.clear();
}

}  // namespace eomc::model
