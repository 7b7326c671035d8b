#include "mechanics/inverse/multiplier.hpp"

#include <algorithm>
#include <exception>
#include <initializer_list>

#include <fmt/format.h>

#include "mechanics/inverse/helmholtz.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/integrate.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;
using namespace detail;

using GiNaC::ex;
using GiNaC::matrix;
using GiNaC::symbol;

namespace {

// One degree of freedom: H2 is g_t + q̇ g_q + f g_q̇ = −(∂f/∂q̇) g; with g = exp(u),
// u_t + q̇ u_q + f u_q̇ = −∂f/∂q̇, and the separable u = G(t) + H(q) + K(q̇) are tried.

void one_degree_of_freedom(const model::Model& model, const std::vector<ex>& f_, Multiplier& m) {
    const symbol& t = model.t;
    const symbol& q = model.coordinates[0].q;
    const symbol& v = model.coordinates[0].q_dot;
    const ex f = f_[0], N = m.N(0, 0);
    const ex minus_N = simplified(-N);
    const std::string qn = coordinate(model, 0), vn = qn + "_dot";
    m.steps.push_back({fmt::format("One degree of freedom: H1 and H3 are empty; H2 reads dg/dt = −(∂f/∂{}) g along the "
                                   "motion, a linear first-order PDE for g(t, {}, {}). With g = exp(u): "
                                   "u_t + {} u_{} + f u_{} = −∂f/∂{}.",
                                   vn, qn, vn, vn, qn, vn, vn),
                       {{"−∂f/∂" + vn, minus_N}}});

    auto accept = [&](const ex& u, const std::string& kind, const std::string& how) {
        matrix g(1, 1);
        g(0, 0) = simplified(exp_of(u));
        const auto residuals = helmholtz(model, f_, FlowMatrices{m.N, m.Phi}, g, true);
        if (!all_zero(residuals) || !regular(g)) {
            m.steps.push_back({fmt::format("{}: the candidate g = {} fails H2 on substitution; rejected", kind, text(g(0, 0))), {}});
            return false;
        }
        m.steps.push_back({fmt::format("{}: {}; g = exp(u) satisfies H2 identically (checked by substitution).", kind, how),
                           {{"g", g(0, 0)}}});
        m.g = g;
        m.kind = kind;
        return true;
    };
    auto free_of = [](const ex& e, std::initializer_list<const symbol*> syms) {
        return std::none_of(syms.begin(), syms.end(), [&](const symbol* s) { return e.has(*s); });
    };

    // u = G(t) + H(q): G'(t) + q̇ H'(q) = −∂f/∂q̇, so −∂f/∂q̇ must be affine in q̇.
    {
        const ex b = simplified(derivative(minus_N, v));
        const ex a = simplified(minus_N - v * b);  // not −∂f/∂q̇ at q̇ = 0: that may be a pole
        if (free_of(a, {&q, &v}) && free_of(b, {&t, &v})) {
            const auto G = antiderivative(a, t);
            const auto H = antiderivative(b, q);
            const std::string kind = a.is_zero() && b.is_zero() ? "constant" : b.is_zero() ? "g(t)" : a.is_zero() ? "g(q)" : "g(t)h(q)";
            if (G && H &&
                accept(*G + *H, kind,
                       fmt::format("−∂f/∂{} = G'(t) + {} H'({}) with G' = {}, H' = {}", vn, vn, qn, text(a), text(b))))
                return;
        } else {
            m.steps.push_back({fmt::format("g(t)h({}): −∂f/∂{} is not of the form a(t) + {} b({})", qn, vn, vn, qn), {}});
        }
    }
    // u = K(q̇): f K'(q̇) = −∂f/∂q̇, so −(∂f/∂q̇)/f must depend on q̇ alone.
    if (!simplified(f).is_zero()) {
        const ex c = simplified(minus_N / f);
        if (free_of(c, {&t, &q})) {
            if (const auto K = antiderivative(c, v);
                K && accept(*K, "g(" + vn + ")", fmt::format("K'({}) = −(∂f/∂{})/f = {}", vn, vn, text(c))))
                return;
        } else {
            m.steps.push_back({fmt::format("g({}): −(∂f/∂{})/f = {} depends on more than {}", vn, vn, text(c), vn), {}});
        }
    }
    // u = G(t) + K(q̇): differentiating in q gives f_q K' = −∂²f/∂q̇∂q, so K' = −f_{q̇q}/f_q.
    if (const ex fq = simplified(derivative(f, q)); !fq.is_zero()) {
        const ex c = simplified(-derivative(N, q) / fq);
        const ex a = simplified(minus_N - f * c);
        if (free_of(c, {&t, &q}) && free_of(a, {&q, &v})) {
            const auto G = antiderivative(a, t);
            const auto K = antiderivative(c, v);
            if (G && K && accept(*G + *K, "g(t)k(" + vn + ")",
                                 fmt::format("K'({}) = −f_{{{}{}}}/f_{} = {}, G'(t) = {}", vn, vn, qn, qn, text(c), text(a))))
                return;
        } else {
            m.steps.push_back({fmt::format("g(t)k({}): no separation (K' = {}, G' = {})", vn, text(c), text(a)), {}});
        }
    }
    // u = H(q) + K(q̇): differentiating in t gives f_t K' = −∂²f/∂q̇∂t, so K' = −f_{q̇t}/f_t.
    if (const ex ft = simplified(derivative(f, t)); !ft.is_zero()) {
        const ex c = simplified(-derivative(N, t) / ft);
        const ex b = simplified((minus_N - f * c) / v);
        if (free_of(c, {&t, &q}) && free_of(b, {&t, &v})) {
            const auto H = antiderivative(b, q);
            const auto K = antiderivative(c, v);
            if (H && K && accept(*H + *K, "h(q)k(" + vn + ")",
                                 fmt::format("K'({}) = −f_{{{}t}}/f_t = {}, H'({}) = {}", vn, vn, text(c), qn, text(b))))
                return;
        } else {
            m.steps.push_back({fmt::format("h({})k({}): no separation (K' = {}, H' = {})", qn, vn, text(c), text(b)), {}});
        }
    }
    m.steps.push_back({"No multiplier of the separable forms g(t)h(q), g(q̇), g(t)k(q̇), h(q)k(q̇) solves H2. "
                       "(In one degree of freedom a multiplier always exists locally — Darboux — but it need not be "
                       "of these forms.)",
                       {}});
}

// ---- n degrees of freedom: ansätze whose conditions H1–H3 are linear in unknown constants.

// Records what an ansatz gave in m: true when it is a regular multiplier, verified by substitution.
bool accept_ansatz(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget,
                   const AnsatzResult& r, const std::string& kind, Multiplier& m) {
    if (r.over_budget) {
        const std::string why = fmt::format("the {} ansatz's conditions H1–H3 have {} expression nodes, over the "
                                            "budget of {}",
                                            kind, r.over_budget, budget.nodes);
        m.undecided += (m.undecided.empty() ? "" : "; ") + why;
        m.steps.push_back({kind + ": not solved: " + why, {}});
        return false;
    }
    if (!r.any) {
        m.steps.push_back({kind + ": H1–H3 leave only g = 0", {}});
        return false;
    }
    if (!r.g) {
        m.steps.push_back({fmt::format("{}: H1–H3 allow g = {} ({} free constant{}), singular for every choice tried",
                                       kind, matrix_text(r.family), r.free.size(), r.free.size() == 1 ? "" : "s"),
                           {}});
        return false;
    }
    if (!all_zero(helmholtz(model, f, FlowMatrices{m.N, m.Phi}, *r.g, true))) {
        m.steps.push_back({kind + ": the candidate fails H1–H3 on substitution; rejected", {}});
        return false;
    }
    m.steps.push_back({fmt::format("{}: H1–H3 hold for g = {} ({} free constant{}); the member chosen is regular",
                                   kind, matrix_text(r.family), r.free.size(), r.free.size() == 1 ? "" : "s"),
                       {}});
    m.g = r.g;
    m.kind = kind;
    m.family = r.family;
    m.free_constants = r.free;
    return true;
}

bool constant_multiplier(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget,
                         Multiplier& m) {
    const Ansatz a = constant_ansatz(model);
    const AnsatzResult r = solve_ansatz(model, f, FlowMatrices{m.N, m.Phi}, a.g, a.unknowns, a.on_diagonal, budget);
    return accept_ansatz(model, f, budget, r, "constant", m);
}

// Diagonal g_ii = c_i exp(φ_i(t, q)): the diagonal part of H2 reads dφ_i/dt = −∂f_i/∂q̇_i,
// so −∂f_i/∂q̇_i must be a_i(t,q) + q̇_k b_ik(t,q) with (a_i, b_i) a gradient in (t, q).
bool diagonal_multiplier(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget,
                         Multiplier& m) {
    const unsigned n = unsigned(model.coordinates.size());
    matrix g(n, n);
    std::vector<symbol> unknowns;
    std::vector<symbol> vars{model.t};
    for (const auto& c : model.coordinates) vars.push_back(c.q);
    bool depends_t = false, depends_q = false;
    for (unsigned i = 0; i < n; ++i) {
        const ex minus = simplified(-m.N(i, i));
        std::vector<ex> gradient{minus};  // [0]: the part free of q̇, completed below
        for (const auto& c : model.coordinates) {
            gradient.push_back(simplified(derivative(minus, c.q_dot)));
            gradient[0] -= c.q_dot * gradient.back();
        }
        gradient[0] = simplified(gradient[0]);
        const bool affine = std::none_of(gradient.begin(), gradient.end(), [&](const ex& e) { return has_velocity(model, e); });
        const auto phi = affine ? potential(gradient, vars) : std::nullopt;
        if (!phi) {
            m.steps.push_back({fmt::format("diagonal: −∂f_{0}/∂{0}_dot = {1} is not the rate of change of a function "
                                           "of t and q along the motion",
                                           coordinate(model, i), text(minus)),
                               {}});
            return false;
        }
        depends_t = depends_t || phi->has(model.t);
        for (const auto& c : model.coordinates) depends_q = depends_q || phi->has(c.q);
        unknowns.emplace_back(fmt::format("c_{}", coordinate(model, i)), fmt::format("c_{{{}}}", coordinate(model, i)));
        g(i, i) = unknowns.back() * simplified(exp_of(*phi));
    }
    const std::string kind = depends_t && depends_q ? "diagonal in t and q"
                             : depends_q            ? "diagonal in q"
                             : depends_t            ? "diagonal in t"
                                                    : "constant diagonal";
    const AnsatzResult r =
        solve_ansatz(model, f, FlowMatrices{m.N, m.Phi}, g, unknowns, std::vector<bool>(n, true), budget);
    return accept_ansatz(model, f, budget, r, kind, m);
}

void several_degrees_of_freedom(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget,
                                Multiplier& m) {
    m.steps.push_back({"n degrees of freedom: first the algebraic consequences of H1 and H2, then constant and "
                       "diagonal multipliers, whose conditions H1–H3 are linear in unknown constant coefficients "
                       "(solved identically in t, q, q̇).",
                       {}});
    if (singular_forced(model, f, budget, m)) {
        m.singular_forced = true;
        return;
    }
    if (constant_multiplier(model, f, budget, m) || diagonal_multiplier(model, f, budget, m)) return;
    m.steps.push_back({"No constant or diagonal multiplier satisfies H1–H3; the question is left open (a multiplier "
                       "of another form may exist).",
                       {}});
}

}  // namespace

Multiplier search_multiplier(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget) {
    Multiplier m;
    const FlowMatrices fm = flow_matrices(model, f);
    m.N = fm.N;
    m.Phi = fm.Phi;
    try {
        if (model.coordinates.size() == 1) one_degree_of_freedom(model, f, m);
        else several_degrees_of_freedom(model, f, budget, m);
    } catch (const std::exception& e) {  // a pole met while substituting, or a GiNaC limit
        m.g.reset();
        m.undecided = std::string("GiNaC stopped it: ") + e.what();
        m.steps.push_back({std::string("The search stopped: ") + e.what(), {}});
    }
    if (m.g) m.undecided.clear();  // a verified multiplier decides, whatever was cut short before it
    return m;
}

}  // namespace eomc::mechanics::inverse
