#include "mechanics/rigid/integrals.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace eomc::mechanics::rigid {

using GiNaC::ex;

RigidIntegrals search_rigid_integrals(const model::Model& model, const EulerPoisson& system, unsigned degree,
                                      std::size_t work_budget) {
    const model::RigidBody& body = *model.rigid;
    RigidIntegrals out;
    out.degree = degree;
    // The search is exact: each parameter must be the short decimal the scene wrote.
    GiNaC::exmap exact;
    for (const auto& p : model.parameters) {
        const auto r = rational_from_decimal(p.value);
        if (!r) {
            out.not_searched = fmt::format("the parameter '{}' = {} is not a short decimal, so the search has no exact "
                                           "value for it",
                                           p.name, p.value);
            return out;
        }
        exact[p.symbol] = *r;
    }
    IntegralSearchInput in;
    for (std::size_t i = 0; i < 3; ++i) in.state.push_back(body.omega[i]);
    for (std::size_t i = 0; i < 3; ++i) in.state.push_back(body.gamma[i]);
    for (std::size_t i = 0; i < 3; ++i) in.field.push_back(system.omega_rate[i].subs(exact).expand());
    for (std::size_t i = 0; i < 3; ++i) in.field.push_back(system.gamma_rate[i].subs(exact).expand());
    const ex* area = nullptr;
    for (const auto& inv : system.integrals) {
        in.known.push_back({inv.name, inv.value.subs(exact).expand()});
        if (inv.name == "area") area = &inv.value;
    }
    if (area) in.conditions.push_back({"area", area->subs(exact).expand(), 0});
    // Degree by degree, each new integral joining the known ones: a product of integrals found
    // at a lower degree (|Iω|²·H for a free body) is then no new integral at a higher one.
    try {
        for (unsigned d = 1; d <= degree; ++d) {
            in.degree = d;
            in.work_budget = std::max<std::size_t>(1, work_budget - out.work);  // 0 would mean no budget
            std::size_t spent = 0;
            std::vector<FoundIntegral> at_d;
            try {
                at_d = search_polynomial_integrals(in, &spent);
            } catch (const SearchBudgetExhausted& e) {
                out.work += e.spent;
                out.undecided = fmt::format("undecided at degree {}: the search stopped after its budget of {} entry "
                                            "operations (--search-budget); the integrals of degree ≤ {} are decided",
                                            d, work_budget, d - 1);
                break;
            }
            out.work += spent;
            for (auto& f : at_d) {
                const bool repeated = std::any_of(out.found.begin(), out.found.end(), [&](const FoundIntegral& g) {
                    return g.conditional == f.conditional && (g.value - f.value).expand().is_zero();
                });
                if (repeated) continue;
                if (!f.conditional) in.known.push_back({fmt::format("found_{}", out.found.size() + 1), f.value});
                out.found.push_back(std::move(f));
            }
        }
    } catch (const std::invalid_argument& e) {
        out.not_searched = e.what();
        out.found.clear();
        return out;
    }
    // The state at t = 0, to decide whether it lies on a conditional integral's level.
    GiNaC::exmap initial = exact;
    for (std::size_t i = 0; i < 3; ++i) {
        initial[body.omega[i]] = GiNaC::numeric(body.omega0[i]);
        initial[body.gamma[i]] = GiNaC::numeric(body.vertical0[i]);
    }
    for (std::size_t k = 0; k < out.found.size(); ++k) {
        const FoundIntegral& f = out.found[k];
        out.names.push_back(f.conditional ? fmt::format("conditional_{}_{}", f.degree, k + 1)
                                          : fmt::format("integral_{}_{}", f.degree, k + 1));
        bool on_level = !f.conditional;
        if (f.conditional && area) {
            // On the level to the initial state's rounding: |K·γ| against |K| |γ|.
            const double value = GiNaC::ex_to<GiNaC::numeric>(area->subs(initial).evalf()).to_double();
            double scale = 0;
            for (std::size_t i = 0; i < 3; ++i) scale += std::abs(body.omega0[i]);
            on_level = std::abs(value) <= 1e-12 * (1 + scale);
        }
        out.tracked.push_back(on_level);
    }
    return out;
}

std::vector<Invariant> tracked_invariants(const RigidIntegrals& integrals) {
    std::vector<Invariant> out;
    for (std::size_t k = 0; k < integrals.found.size(); ++k) {
        if (!integrals.tracked[k]) continue;
        const FoundIntegral& f = integrals.found[k];
        out.push_back({integrals.names[k], f.value,
                       f.conditional ? fmt::format("a polynomial integral of degree {} found by undetermined "
                                                   "coefficients at the scene's parameter values; it {}, where the "
                                                   "motion starts",
                                                   f.degree, f.condition_name)
                                     : fmt::format("a polynomial integral of degree {} found by undetermined "
                                                   "coefficients at the scene's parameter values (not a polynomial in "
                                                   "the energy, area and geometric integrals)",
                                                   f.degree)});
    }
    return out;
}

}  // namespace eomc::mechanics::rigid
