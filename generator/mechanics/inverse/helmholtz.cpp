#include "mechanics/inverse/helmholtz.hpp"

#include <algorithm>
#include <exception>

#include <fmt/format.h>

#include "symbolic/differentiation.hpp"
#include "symbolic/simplify.hpp"
#include "symbolic/solve.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::matrix;
using GiNaC::symbol;

namespace detail {

FlowMatrices flow_matrices(const model::Model& model, const std::vector<ex>& f) {
    const unsigned n = unsigned(model.coordinates.size());
    FlowMatrices m{matrix(n, n), matrix(n, n)};
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) m.N(i, j) = simplified(derivative(f[i], model.coordinates[j].q_dot));
    const matrix N2 = m.N.mul(m.N);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
            m.Phi(i, j) = simplified(along_motion(model, f, m.N(i, j)) / 2 - derivative(f[i], model.coordinates[j].q) -
                                     N2(i, j) / 4);
    return m;
}

std::vector<std::pair<std::string, ex>> helmholtz(const model::Model& model, const std::vector<ex>& f,
                                                  const FlowMatrices& m, const matrix& g, bool simplify) {
    const unsigned n = unsigned(model.coordinates.size());
    std::vector<std::pair<std::string, ex>> out;
    auto put = [&](std::string name, const ex& value) { out.emplace_back(std::move(name), simplify ? simplified(value) : value); };
    const matrix gPhi = g.mul(m.Phi);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i + 1; j < n; ++j)
            put(fmt::format("H1({},{})", coordinate(model, i), coordinate(model, j)), gPhi(i, j) - gPhi(j, i));
    const matrix NtG = m.N.transpose().mul(g), GN = g.mul(m.N);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j)
            put(fmt::format("H2({},{})", coordinate(model, i), coordinate(model, j)),
                along_motion(model, f, g(i, j)) + NtG(i, j) / 2 + GN(i, j) / 2);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
            for (unsigned k = j + 1; k < n; ++k)
                put(fmt::format("H3({};{},{})", coordinate(model, i), coordinate(model, j), coordinate(model, k)),
                    derivative(g(i, j), model.coordinates[k].q_dot) - derivative(g(i, k), model.coordinates[j].q_dot));
    return out;
}

bool all_zero(const std::vector<std::pair<std::string, ex>>& residuals) {
    return std::all_of(residuals.begin(), residuals.end(), [](const auto& r) { return r.second.is_zero(); });
}

bool regular(const matrix& g) {
    try {
        return !simplified(g.determinant()).is_zero();
    } catch (const std::exception&) {
        return false;
    }
}

namespace {

// A regular member of the family g(free): free diagonal constants 1 and the others 0
// first (the plainest member), then each free constant alone, then all of them 1.
std::optional<matrix> regular_member(const matrix& family, const std::vector<symbol>& free,
                                     const std::vector<bool>& on_diagonal) {
    std::vector<GiNaC::exmap> tries;
    GiNaC::exmap diagonal;
    for (std::size_t i = 0; i < free.size(); ++i) diagonal[free[i]] = on_diagonal[i] ? 1 : 0;
    tries.push_back(diagonal);
    for (std::size_t i = 0; i < free.size(); ++i) {
        GiNaC::exmap unit;
        for (std::size_t k = 0; k < free.size(); ++k) unit[free[k]] = k == i ? 1 : 0;
        tries.push_back(unit);
    }
    GiNaC::exmap ones;
    for (const auto& s : free) ones[s] = 1;
    tries.push_back(ones);
    for (const auto& values : tries) {
        matrix g = ex_to<matrix>(family.subs(values));
        for (unsigned i = 0; i < g.rows(); ++i)
            for (unsigned j = 0; j < g.cols(); ++j) g(i, j) = simplified(g(i, j));
        if (regular(g)) return g;
    }
    return std::nullopt;
}

}  // namespace

AnsatzResult solve_ansatz(const model::Model& model, const std::vector<ex>& f, const FlowMatrices& m,
                          const matrix& ansatz, const std::vector<symbol>& unknowns,
                          const std::vector<bool>& unknown_on_diagonal, const SearchBudget& budget) {
    AnsatzResult r;
    std::vector<ex> conditions;
    std::size_t size = 0;
    for (const auto& [name, value] : helmholtz(model, f, m, ansatz, false)) {
        conditions.push_back(value);
        size += node_count(value);
    }
    if (size > budget.nodes) {
        r.over_budget = size;
        return r;
    }
    const auto solution = solve_identically(conditions, unknowns, state_symbols(model));
    if (!solution) return r;
    r.family = ex_to<matrix>(ansatz.subs(*solution));
    std::vector<bool> diagonal;
    for (std::size_t i = 0; i < unknowns.size(); ++i) {
        const ex value = solution->at(unknowns[i]);
        if (value.is_equal(unknowns[i])) {
            r.free.push_back(unknowns[i]);
            diagonal.push_back(unknown_on_diagonal[i]);
        }
    }
    r.any = !r.free.empty();
    if (r.any) r.g = regular_member(r.family, r.free, diagonal);
    return r;
}

Ansatz constant_ansatz(const model::Model& model) {
    const unsigned n = unsigned(model.coordinates.size());
    Ansatz a{matrix(n, n), {}, {}};
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j) {
            a.unknowns.emplace_back(fmt::format("c_{}_{}", coordinate(model, i), coordinate(model, j)),
                                    fmt::format("c_{{{}{}}}", coordinate(model, i), coordinate(model, j)));
            a.on_diagonal.push_back(i == j);
            a.g(i, j) = a.g(j, i) = a.unknowns.back();
        }
    return a;
}

}  // namespace detail

std::vector<std::pair<std::string, ex>> helmholtz_residuals(const model::Model& model, const std::vector<ex>& f,
                                                            const matrix& g) {
    return detail::helmholtz(model, f, detail::flow_matrices(model, f), g, true);
}

FundamentalForm multiplied(const matrix& g, const std::vector<ex>& f) {
    const unsigned n = g.rows();
    FundamentalForm out{matrix(n, n), {}};
    for (unsigned i = 0; i < n; ++i) {
        ex b = 0;
        for (unsigned j = 0; j < n; ++j) {
            out.A(i, j) = simplified(g(i, j));
            b -= g(i, j) * f[j];
        }
        out.B.push_back(simplified(b));
    }
    return out;
}

}  // namespace eomc::mechanics::inverse
