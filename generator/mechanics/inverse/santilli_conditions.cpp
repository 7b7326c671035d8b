#include "mechanics/inverse/santilli_conditions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;
using namespace detail;

using GiNaC::ex;

std::string label(const model::Model& model, const Residual& r) {
    if (r.condition == "S2") return fmt::format("S2({};{},{})", coordinate(model, r.i), coordinate(model, r.j), coordinate(model, *r.k));
    if (r.condition == "S4") return fmt::format("S4({},{};{})", coordinate(model, r.i), coordinate(model, r.j), coordinate(model, *r.k));
    return fmt::format("{}({},{})", r.condition, coordinate(model, r.i), coordinate(model, r.j));
}

std::vector<Residual> santilli_conditions(const model::Model& model, const FundamentalForm& form) {
    const std::size_t n = model.coordinates.size();
    const auto& A = form.A;
    const auto& B = form.B;
    auto a = [&](std::size_t i, std::size_t j) { return A(unsigned(i), unsigned(j)); };
    auto qd = [&](std::size_t k) { return model.coordinates[k].q_dot; };
    auto q = [&](std::size_t k) { return model.coordinates[k].q; };
    // ∂B_i/∂q̇_j − ∂B_j/∂q̇_i, used by S4 and S5
    auto curl_B = [&](std::size_t i, std::size_t j) { return derivative(B[i], qd(j)) - derivative(B[j], qd(i)); };

    std::vector<Residual> out;
    auto add = [&](const char* name, std::size_t i, std::size_t j, std::optional<std::size_t> k, const ex& value) {
        Residual r{name, i, j, k, simplified(value), false};
        r.zero = r.value.is_zero();
        out.push_back(std::move(r));
    };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) add("S1", i, j, std::nullopt, a(i, j) - a(j, i));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t k = j + 1; k < n; ++k)
                add("S2", i, j, k, derivative(a(i, j), qd(k)) - derivative(a(i, k), qd(j)));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i; j < n; ++j)
            add("S3", i, j, std::nullopt, derivative(B[i], qd(j)) + derivative(B[j], qd(i)) - 2 * total_derivative(model, a(i, j)));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (std::size_t k = 0; k < n; ++k)
                add("S4", i, j, k,
                    derivative(a(i, k), q(j)) - derivative(a(j, k), q(i)) - derivative(curl_B(i, j), qd(k)) / 2);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            add("S5", i, j, std::nullopt,
                derivative(B[i], q(j)) - derivative(B[j], q(i)) - total_derivative(model, curl_B(i, j)) / 2);
    return out;
}

Decision decide(const model::Model& model, const std::vector<Residual>& residuals) {
    Decision d;
    const auto points = probe_points(model, probe_count, 0x5a17111);
    bool all_zero = true;
    for (std::size_t r = 0; r < residuals.size(); ++r) {
        if (residuals[r].zero) continue;
        all_zero = false;
        std::size_t finite = 0;
        for (const auto& point : points) {
            const double v = evaluate(residuals[r].value, point);
            if (!std::isfinite(v)) continue;
            ++finite;
            // 1e-9 relative: far above round-off of a few hundred operations, far below
            // any genuinely non-zero residual at a random point.
            if (std::abs(v) > 1e-9 * magnitude(residuals[r].value, point) && std::abs(v) > 1e-300) {
                d.verdict = Verdict::not_self_adjoint;
                d.witness = r;
                d.witness_value = v;
                d.point.emplace_back("t", point.values.at(model.t));
                for (const auto& c : model.coordinates) d.point.emplace_back(c.name, point.values.at(c.q));
                for (const auto& c : model.coordinates) d.point.emplace_back(c.name + "_dot", point.values.at(c.q_dot));
                for (const auto& p : model.parameters) d.point.emplace_back(p.name, point.values.at(p.symbol));
                return d;
            }
        }
        d.unresolved.push_back(r);
        d.points_tried = std::max(d.points_tried, finite);
    }
    d.verdict = all_zero ? Verdict::self_adjoint : Verdict::undecided;
    return d;
}

}  // namespace eomc::mechanics::inverse
