#include "mechanics/inverse/inverse_problem.hpp"

#include <fmt/format.h>

#include "mechanics/inverse/helmholtz.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/simplify.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;
using namespace detail;

using GiNaC::ex_to;
using GiNaC::matrix;

namespace {

bool proportional(const matrix& a, const matrix& b) {
    const unsigned n = a.rows();
    for (unsigned i = 0; i < n * n; ++i)
        for (unsigned j = 0; j < n * n; ++j)
            if (!simplified(a(i / n, i % n) * b(j / n, j % n) - a(j / n, j % n) * b(i / n, i % n)).is_zero()) return false;
    return true;
}

// Another Lagrangian for equations already self-adjoint: a regular constant multiplier not
// proportional to A (the multiplier the equations carry as given) gives different equations
// with the same solutions, hence an inequivalent Lagrangian.
std::optional<Alternative> alternative_lagrangian(const model::Model& model, const Forms& forms) {
    const FlowMatrices fm = flow_matrices(model, forms.kinematic);
    const Ansatz a = constant_ansatz(model);
    const AnsatzResult r = solve_ansatz(model, forms.kinematic, fm, a.g, a.unknowns, a.on_diagonal, SearchBudget{});
    if (r.free.size() < 2) return std::nullopt;
    for (std::size_t k = 0; k < r.free.size(); ++k) {
        GiNaC::exmap unit;
        for (std::size_t l = 0; l < r.free.size(); ++l) unit[r.free[l]] = l == k ? 1 : 0;
        matrix member = ex_to<matrix>(r.family.subs(unit));
        if (!regular(member) || proportional(member, forms.fundamental.A)) continue;
        Alternative alt{member, construct_lagrangian(model, multiplied(member, forms.kinematic))};
        if (alt.construction.built && alt.construction.verified) return alt;
    }
    return std::nullopt;
}

// The verdict on S1–S5, as the first clause of Analysis::reason.
std::string verdict_sentence(const model::Model& model, const Analysis& a) {
    switch (a.decision.verdict) {
        case Verdict::self_adjoint: return "self-adjoint as given (S1–S5 hold identically)";
        case Verdict::not_self_adjoint:
            return fmt::format("not self-adjoint ({} = {} ≠ 0)", label(model, a.conditions[a.decision.witness]),
                               text(a.conditions[a.decision.witness].value));
        case Verdict::undecided:
            return fmt::format("undecided ({} residual{} GiNaC cannot simplify vanish at {} random points)",
                               a.decision.unresolved.size(), a.decision.unresolved.size() == 1 ? "" : "s",
                               a.decision.points_tried);
    }
    return {};
}

}  // namespace

Analysis analyse(const model::Model& model, const Equations& equations, const SearchBudget& budget) {
    // The inverse problem is posed for the free equations M q̈ = f; constraint reactions are not part of them.
    if (!model.constraints.empty())
        throw InputError(model.constraints.front().pos,
                         fmt::format("`eomc inverse` does not support constrained scenes ([[constraint]] '{}'): the "
                                     "inverse problem is posed for unconstrained equations of motion",
                                     model.constraints.front().name));
    Analysis a;
    a.forms = forms(model, equations);
    a.conditions = santilli_conditions(model, a.forms.fundamental);
    a.decision = decide(model, a.conditions);
    const bool construct = model.inverse.construct;

    const std::string verdict = verdict_sentence(model, a);

    const FundamentalForm* target = nullptr;
    std::string how;
    if (a.decision.verdict != Verdict::not_self_adjoint) {
        target = &a.forms.fundamental;
    } else if (model.inverse.multiplier_search) {
        a.multiplier = search_multiplier(model, a.forms.kinematic, budget);
        if (a.multiplier->g) {
            a.multiplied_form = multiplied(*a.multiplier->g, a.forms.kinematic);
            a.multiplied_conditions = santilli_conditions(model, *a.multiplied_form);
            target = &*a.multiplied_form;
            how = fmt::format("; the multiplier g = {} ({}) makes g (q̈ − f) self-adjoint", matrix_text(*a.multiplier->g),
                              a.multiplier->kind);
        } else if (a.multiplier->singular_forced) {
            how = "; H1–H2 force every multiplier to be singular: no regular Lagrangian exists";
        } else if (!a.multiplier->undecided.empty()) {
            how = "; the multiplier search is undecided: " + a.multiplier->undecided +
                  " (no multiplier among the forms it reached)";
        } else {
            how = "; no multiplier of the forms tried";
        }
    } else {
        how = "; multiplier search is off ([inverse] multiplier_search = false)";
    }

    std::string built;
    if (target && construct) {
        a.construction = construct_lagrangian(model, *target);
        if (!a.construction->built) built = "; no Lagrangian built: " + a.construction->reason;
        else if (a.construction->verified) built = "; L constructed and ε(L) = E verified symbolically";
        else
            built = fmt::format("; L constructed but ε(L) = E not proven symbolically (agrees at {} of {} random points)",
                                a.construction->points_agreeing, probe_count);
        if (a.decision.verdict == Verdict::self_adjoint && model.coordinates.size() >= 2)
            a.alternative = alternative_lagrangian(model, a.forms);
        if (a.alternative)
            built += fmt::format("; another Lagrangian from the multiplier {} (verified): the Lagrangian is not unique",
                                 matrix_text(a.alternative->g));
    } else if (target) {
        built = "; construction is off ([inverse] construct = false)";
    }
    a.reason = verdict + how + built;
    return a;
}

}  // namespace eomc::mechanics::inverse
