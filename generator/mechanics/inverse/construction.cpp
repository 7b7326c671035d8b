#include "mechanics/inverse/construction.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <optional>

#include <fmt/format.h>

#include "mechanics/kinematics/operators.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/integrate.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;
using namespace detail;

using GiNaC::ex;
using GiNaC::is_a;
using GiNaC::matrix;
using GiNaC::symbol;

std::vector<ex> euler_lagrange_mismatch(const model::Model& model, const ex& L, const FundamentalForm& form) {
    std::vector<ex> out;
    for (std::size_t i = 0; i < model.coordinates.size(); ++i)
        out.push_back(simplified(euler_operator(model, L, i) - form.expression(model, i)));
    return out;
}

namespace {

// The centres tried for the homotopies, in order: 0 unless the integrands are singular there.
constexpr double centres[] = {0, 1, 2};

// q ↦ q₀ + τ(q − q₀) in every coordinate.
GiNaC::exmap coordinate_ray(const model::Model& model, double q0, const symbol& tau) {
    GiNaC::exmap ray;
    for (const auto& co : model.coordinates) ray[co.q] = q0 + tau * (co.q - q0);
    return ray;
}

// K from A along the ray v₀ + τ(q̇ − v₀), with the first centre v₀ that works.
bool kinetic_part(const model::Model& model, const FundamentalForm& form, const symbol& tau, Construction& c) {
    const std::size_t n = model.coordinates.size();
    for (double v0 : centres) {
        GiNaC::exmap ray;
        for (const auto& co : model.coordinates) ray[co.q_dot] = v0 + tau * (co.q_dot - v0);
        ex K = 0;
        bool ok = true;
        for (std::size_t i = 0; i < n && ok; ++i)
            for (std::size_t j = 0; j < n && ok; ++j) {
                const ex a = form.A(unsigned(i), unsigned(j));
                if (a.is_zero()) continue;
                const auto I = unit_integral((1 - tau) * a.subs(ray), tau);
                if (!I) ok = false;
                else K += (model.coordinates[i].q_dot - v0) * (model.coordinates[j].q_dot - v0) * *I;
            }
        if (ok) {
            c.K = simplified(K);
            c.v_centre = v0;
            return true;
        }
    }
    c.reason = "the integral ∫₀¹ (1−τ) A(t, q, τq̇) dτ for K is out of reach of the integrator";
    return false;
}

// E_i − ε_i(K) = α_i + β_ik q̇_k (no q̈ left: ∂²K/∂q̇∂q̇ = A), with β antisymmetric: what S1–S5
// guarantee, checked here because the construction relies on it.
bool velocity_split(const model::Model& model, const FundamentalForm& form, Construction& c) {
    const std::size_t n = model.coordinates.size();
    c.beta = matrix(unsigned(n), unsigned(n));
    for (std::size_t i = 0; i < n; ++i) {
        ex R = simplified(form.expression(model, i) - euler_operator(model, c.K, i));
        // R is affine in q̈ and its q̈ coefficients A − ∂²K/∂q̇∂q̇ must vanish (they may only
        // look non-zero, e.g. through square roots the simplifier does not merge).
        GiNaC::exmap no_acceleration;
        for (const auto& co : model.coordinates) {
            if (!R.has(co.q_ddot)) continue;
            if (!simplified(derivative(R, co.q_ddot)).is_zero()) {
                c.reason = "E − ε(K) still contains accelerations: A is not the Hessian of K (S1 or S2 fails)";
                return false;
            }
            no_acceleration[co.q_ddot] = 0;
        }
        if (!no_acceleration.empty()) R = simplified(R.subs(no_acceleration));
        // α = R − β q̇ rather than R at q̇ = 0: R may hold terms (log q̇) that cancel only
        // after simplification and cannot be evaluated at rest.
        ex alpha = R;
        bool affine = true;
        for (std::size_t k = 0; k < n; ++k) {
            const ex b = simplified(derivative(R, model.coordinates[k].q_dot));
            c.beta(unsigned(i), unsigned(k)) = b;
            alpha -= b * model.coordinates[k].q_dot;
            affine = affine && !has_velocity(model, b);
        }
        alpha = simplified(alpha);
        // Terms of α that only look velocity-dependent (a factor that is zero but not
        // simplified away) go with a substitution q̇ = 0 once ∂α/∂q̇ is shown to vanish.
        bool velocity_free = !has_velocity(model, alpha);
        if (!velocity_free && affine) {
            velocity_free = std::all_of(model.coordinates.begin(), model.coordinates.end(), [&](const auto& co) {
                return simplified(derivative(alpha, co.q_dot)).is_zero();
            });
            GiNaC::exmap at_rest;
            for (const auto& co : model.coordinates) at_rest[co.q_dot] = 0;
            try {
                if (velocity_free) alpha = simplified(alpha.subs(at_rest));
            } catch (const std::exception&) {  // a pole at rest: keep α as it is
            }
        }
        c.alpha.push_back(alpha);
        if (!affine || !velocity_free) {
            c.reason = fmt::format("E − ε(K) for '{}' is not affine in the velocities (S3–S5 fail)", coordinate(model, i));
            return false;
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < n; ++k)
            if (!simplified(c.beta(unsigned(i), unsigned(k)) + c.beta(unsigned(k), unsigned(i))).is_zero()) {
                c.reason = "the velocity part β of E − ε(K) is not antisymmetric (S3 fails)";
                return false;
            }
    return true;
}

// D_i from β by the homotopy q₀ + τ(q − q₀), with the first centre q₀ that works.
bool gyroscopic_part(const model::Model& model, const symbol& tau, Construction& c) {
    const std::size_t n = model.coordinates.size();
    for (double q0 : centres) {
        const GiNaC::exmap ray = coordinate_ray(model, q0, tau);
        std::vector<ex> D;
        for (std::size_t i = 0; i < n; ++i) {
            ex integrand = 0;
            for (std::size_t k = 0; k < n; ++k)
                integrand += (model.coordinates[k].q - q0) * c.beta(unsigned(i), unsigned(k)).subs(ray);
            const auto I = simplified(integrand).is_zero() ? std::optional<ex>(ex(0)) : unit_integral(tau * integrand, tau);
            if (!I) break;
            D.push_back(*I);
        }
        if (D.size() == n) {
            c.D = D;
            return true;
        }
    }
    c.reason = "the homotopy integral for D is out of reach of the integrator";
    return false;
}

// C from ∂_i C = ∂_t D_i − α_i by the homotopy q₀ + τ(q − q₀), with the first centre q₀ that
// works; else one coordinate after another.
bool potential_part(const model::Model& model, const symbol& tau, Construction& c) {
    const std::size_t n = model.coordinates.size();
    std::vector<ex> gradient_C;
    for (std::size_t i = 0; i < n; ++i) gradient_C.push_back(derivative(c.D[i], model.t) - c.alpha[i]);
    std::optional<ex> C;
    for (double q0 : centres) {
        const GiNaC::exmap ray = coordinate_ray(model, q0, tau);
        ex integrand = 0;
        for (std::size_t i = 0; i < n; ++i) integrand += (model.coordinates[i].q - q0) * gradient_C[i].subs(ray);
        C = simplified(integrand).is_zero() ? std::optional<ex>(ex(0)) : unit_integral(integrand, tau);
        if (C) {
            c.q_centre = q0;
            break;
        }
    }
    if (!C) {
        // A potential singular at every centre tried (k/|q| in Cartesian coordinates): C by
        // integrating one coordinate after another instead of along rays.
        std::vector<symbol> coordinates;
        for (const auto& co : model.coordinates) coordinates.push_back(co.q);
        C = potential(gradient_C, coordinates);
        c.C_by_coordinates = bool(C);
    }
    if (!C) {
        c.reason = "the integrals for C are out of reach of the integrator";
        return false;
    }
    c.C = *C;
    return true;
}

// L = K + D_k q̇_k + C without additive constants (from the homotopy centres: they change no
// equation).
ex assembled(const model::Model& model, const Construction& c) {
    ex L = c.K + c.C;
    for (std::size_t i = 0; i < model.coordinates.size(); ++i) L += c.D[i] * model.coordinates[i].q_dot;
    L = simplified(L);
    const auto state = state_symbols(model);
    if (is_a<GiNaC::add>(L)) {
        ex kept = 0;
        for (const ex& term : terms_of(L))
            if (depends_on_state(term, state)) kept += term;
        L = kept;
    }
    return L;
}

// ε(L) = E symbolically; when that does not simplify, the random points where it holds to round-off.
void verify(const model::Model& model, const FundamentalForm& form, Construction& c) {
    c.check = euler_lagrange_mismatch(model, c.L, form);
    c.verified = std::all_of(c.check.begin(), c.check.end(), [](const ex& e) { return e.is_zero(); });
    if (c.verified) return;
    for (const auto& point : probe_points(model, probe_count, 0xc0ffee)) {
        bool agree = true;
        for (const ex& e : c.check) {
            const double v = evaluate(e, point);
            if (!std::isfinite(v) || std::abs(v) > 1e-9 * (1 + magnitude(e, point))) agree = false;
        }
        if (agree) ++c.points_agreeing;
    }
}

Construction construct(const model::Model& model, const FundamentalForm& form) {
    Construction c;
    const symbol tau("tau", "\\tau");
    if (!kinetic_part(model, form, tau, c) || !velocity_split(model, form, c) || !gyroscopic_part(model, tau, c) ||
        !potential_part(model, tau, c))
        return c;
    c.L = assembled(model, c);
    c.built = true;
    verify(model, form, c);
    return c;
}

}  // namespace

Construction construct_lagrangian(const model::Model& model, const FundamentalForm& form) {
    try {
        return construct(model, form);
    } catch (const std::exception& e) {  // a pole met while substituting, or a GiNaC limit
        Construction c;
        c.reason = std::string("the construction failed: ") + e.what();
        return c;
    }
}

std::pair<ex, ex> split_lagrangian(const model::Model& model, const ex& L) {
    ex T = 0, V = 0;
    for (const ex& term : terms_of(L.expand())) {
        const bool kinetic = std::any_of(model.coordinates.begin(), model.coordinates.end(),
                                         [&](const auto& c) { return term.has(c.q_dot); });
        if (kinetic) T += term;
        else V -= term;
    }
    return {simplified(T), simplified(V)};
}

}  // namespace eomc::mechanics::inverse
