#include "mechanics/inverse/forms.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "symbolic/differentiation.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;

using GiNaC::ex;
using GiNaC::matrix;
using GiNaC::symbol;

ex FundamentalForm::expression(const model::Model& model, std::size_t i) const {
    ex e = B[i];
    for (std::size_t j = 0; j < model.coordinates.size(); ++j) e += A(unsigned(i), unsigned(j)) * model.coordinates[j].q_ddot;
    return e;
}

Forms forms(const model::Model& model, const Equations& equations) {
    const std::size_t n = model.coordinates.size();
    Forms out;
    out.given_fundamental = !(model.newtonian && !model.newtonian->fundamental);
    out.fundamental.A = matrix(unsigned(n), unsigned(n));
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j)
            out.fundamental.A(unsigned(i), unsigned(j)) = simplified(equations.mass_matrix(unsigned(i), unsigned(j)));
        out.fundamental.B.push_back(simplified(-equations.forcing[i]));
    }
    if (!out.given_fundamental) {
        out.kinematic = equations.forcing;
        return out;
    }
    bool identity = true;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (!(out.fundamental.A(unsigned(i), unsigned(j)) - (i == j ? 1 : 0)).is_zero()) identity = false;
    if (identity) {
        for (std::size_t i = 0; i < n; ++i) out.kinematic.push_back(simplified(equations.forcing[i]));
        return out;
    }
    if (n > 4)
        throw std::runtime_error(fmt::format("the kinematic form of {} coordinates needs A⁻¹ symbolically; "
                                             "`eomc inverse` handles up to 4 (or give the kinematic form)",
                                             n));
    const matrix inverse = out.fundamental.A.inverse();
    for (std::size_t i = 0; i < n; ++i) {
        ex f = 0;
        for (std::size_t j = 0; j < n; ++j) f += inverse(unsigned(i), unsigned(j)) * equations.forcing[j];
        out.kinematic.push_back(simplified(f));
    }
    return out;
}

namespace detail {

ex total_derivative(const model::Model& model, const ex& F) {
    ex d = derivative(F, model.t);
    for (const auto& c : model.coordinates) d += c.q_dot * derivative(F, c.q);
    return d;
}

ex along_motion(const model::Model& model, const std::vector<ex>& f, const ex& F) {
    ex d = total_derivative(model, F);
    for (std::size_t k = 0; k < model.coordinates.size(); ++k) d += f[k] * derivative(F, model.coordinates[k].q_dot);
    return d;
}

std::vector<symbol> state_symbols(const model::Model& model) {
    std::vector<symbol> out{model.t};
    for (const auto& c : model.coordinates) {
        out.push_back(c.q);
        out.push_back(c.q_dot);
    }
    return out;
}

bool depends_on_state(const ex& e, const std::vector<symbol>& state) {
    return std::any_of(state.begin(), state.end(), [&](const symbol& s) { return e.has(s); });
}

bool has_velocity(const model::Model& model, const ex& e) {
    return std::any_of(model.coordinates.begin(), model.coordinates.end(), [&](const auto& c) { return e.has(c.q_dot); });
}

std::string coordinate(const model::Model& model, std::size_t i) { return model.coordinates[i].name; }

std::string matrix_text(const matrix& g) {
    std::string out = "[";
    for (unsigned i = 0; i < g.rows(); ++i) {
        out += i ? ", [" : "[";
        for (unsigned j = 0; j < g.cols(); ++j) out += (j ? ", " : "") + text(g(i, j));
        out += "]";
    }
    return out + "]";
}

double magnitude(const ex& e, const ProbePoint& point) {
    double sum = 0;
    for (const ex& term : terms_of(e.expand())) sum += std::abs(evaluate(term, point));
    return sum;
}

}  // namespace detail

}  // namespace eomc::mechanics::inverse
