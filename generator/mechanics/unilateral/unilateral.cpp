#include "mechanics/unilateral/unilateral.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "mechanics/constraints/constraints.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

std::vector<UnilateralRow> unilateral_rows(const model::Model& model) {
    std::vector<UnilateralRow> rows;
    for (const auto& given : model.unilateral) {
        UnilateralRow row{constraint_row(model, given.name, given.holonomic, given.expression, given.pos),
                          given.restitution};
        // The reaction's direction W (Mei, §6.3): without it the row neither constrains nor reacts.
        if (std::all_of(row.row.W.begin(), row.row.W.end(), [](const GiNaC::ex& w) { return GiNaC::normal(w).is_zero(); }))
            throw InputError(given.pos,
                             fmt::format("the unilateral constraint '{}' is degenerate: its row W = {} vanishes "
                                         "identically, so no motion closes or opens it and it has no reaction",
                                         given.name, given.holonomic ? "df/dq" : "dphi/dq_dot"));
        rows.push_back(std::move(row));
    }
    return rows;
}

bool unilateral_reactions_do_no_work(const model::Model& model, const std::vector<UnilateralRow>& rows) {
    std::vector<ConstraintRow> plain;
    for (const auto& r : rows) plain.push_back(r.row);
    return reactions_do_no_work(model, plain);
}

}  // namespace eomc::mechanics
