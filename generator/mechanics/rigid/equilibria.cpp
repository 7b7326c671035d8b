#include "mechanics/rigid/equilibria.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "mechanics/rigid/euler_poisson.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/vector3.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

using D3 = std::array<double, 3>;

double value_of(const ex& e, const GiNaC::exmap& defaults) {
    const ex v = GiNaC::evalf(e.subs(defaults));
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real())
        throw std::runtime_error("rigid equilibria: '" + [&] {
            std::ostringstream s;
            s << e;
            return s.str();
        }() + "' does not evaluate to a real number at the default parameters");
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

D3 values_of(const Vec3& v, const GiNaC::exmap& d) { return {value_of(v[0], d), value_of(v[1], d), value_of(v[2], d)}; }

D3 cross3(const D3& a, const D3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm3(const D3& a) { return std::sqrt(dot3(a, a)); }

// The body's numbers at the defaults.
struct Numbers {
    Eigen::Matrix3d I;
    D3 rc{}, k{};
    double P = 0;
};

Numbers numbers_of(const model::Model& model) {
    const model::RigidBody& b = *model.rigid;
    const GiNaC::exmap d = model.parameter_defaults();
    Numbers n;
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j) n.I(i, j) = value_of(b.inertia(i, j), d);
    n.rc = values_of(b.center, d);
    n.k = values_of(b.gyrostat, d);
    n.P = value_of(b.weight, d);
    return n;
}

D3 times3(const Eigen::Matrix3d& I, const D3& v) {
    const Eigen::Vector3d r = I * Eigen::Vector3d(v[0], v[1], v[2]);
    return {r[0], r[1], r[2]};
}

// (Iω + k) × ω + P γ × r_c.
D3 forcing(const Numbers& n, const D3& w, const D3& g) {
    D3 K = times3(n.I, w);
    for (int i = 0; i < 3; ++i) K[i] += n.k[i];
    const D3 a = cross3(K, w), b = cross3(g, n.rc);
    return {a[0] + n.P * b[0], a[1] + n.P * b[1], a[2] + n.P * b[2]};
}

// The scale of the forcing's terms at (ω, γ), for relative tolerances.
double forcing_scale(const Numbers& n, const D3& w, const D3& g) {
    return n.I.norm() * dot3(w, w) + norm3(n.k) * norm3(w) + std::abs(n.P) * norm3(g) * norm3(n.rc) + 1e-300;
}

std::string axis_label(int axis, int sign) {
    return std::string(sign > 0 ? "+e" : "−e") + std::to_string(axis + 1);
}

// A principal axis of a full inertia matrix: I's eigenvector `axis` (ascending moments).
std::string fmt_axis(int axis, int sign) {
    return std::string(sign > 0 ? "+" : "−") + "principal axis " + std::to_string(axis + 1);
}

}  // namespace

double rotation_residual(const model::Model& model, const D3& gamma, double spin) {
    const Numbers n = numbers_of(model);
    const D3 w{spin * gamma[0], spin * gamma[1], spin * gamma[2]};
    return norm3(forcing(n, w, gamma));
}

double staude_spin_squared(const model::Model& model, const D3& g) {
    const Numbers n = numbers_of(model);
    const D3 a = cross3(g, times3(n.I, g)), c = cross3(g, n.rc);
    return n.P * dot3(c, a) / dot3(a, a);
}

PermanentRotation linearise_rotation(const model::Model& model, const D3& gamma, double spin) {
    const model::RigidBody& body = *model.rigid;
    const GiNaC::exmap defaults = model.parameter_defaults();
    const EulerPoisson s = euler_poisson(body);
    std::array<GiNaC::symbol, 6> x{body.omega[0], body.omega[1], body.omega[2],
                                   body.gamma[0], body.gamma[1], body.gamma[2]};
    std::array<ex, 6> f{s.omega_rate[0], s.omega_rate[1], s.omega_rate[2],
                        s.gamma_rate[0], s.gamma_rate[1], s.gamma_rate[2]};
    GiNaC::exmap at = defaults;
    for (int i = 0; i < 3; ++i) {
        at[body.omega[i]] = spin * gamma[std::size_t(i)];
        at[body.gamma[i]] = gamma[std::size_t(i)];
    }
    Eigen::MatrixXd J(6, 6);
    for (int i = 0; i < 6; ++i) {
        const ex fi = f[std::size_t(i)].subs(defaults);
        for (int j = 0; j < 6; ++j) J(i, j) = value_of(derivative(fi, x[std::size_t(j)]), at);
    }
    PermanentRotation out;
    out.gamma = gamma;
    out.spin = spin;
    const Eigen::EigenSolver<Eigen::MatrixXd> full(J, false);
    for (int i = 0; i < 6; ++i) out.eigenvalues.push_back(full.eigenvalues()[i]);

    // The Casimirs' gradients: ∇|γ|² = (0, 2γ), ∇(K·γ) = (Iγ, Iω + k). J maps onto their
    // orthogonal complement T; with an orthonormal basis Q of T, J Q = Q (Qᵀ J Q).
    const Numbers n = numbers_of(model);
    const D3 Ig = times3(n.I, gamma);
    Eigen::MatrixXd G(6, 2);
    for (int i = 0; i < 3; ++i) {
        G(i, 0) = 0;
        G(3 + i, 0) = 2 * gamma[std::size_t(i)];
        G(i, 1) = Ig[std::size_t(i)];
        G(3 + i, 1) = spin * Ig[std::size_t(i)] + n.k[std::size_t(i)];
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
    const Eigen::MatrixXd Q = Eigen::MatrixXd(qr.householderQ()).rightCols(4);
    const Eigen::MatrixXd JT = Q.transpose() * J * Q;
    const Eigen::EigenSolver<Eigen::MatrixXd> leaf(JT, false);
    double largest = 0, growth = 0;
    for (int i = 0; i < 4; ++i) {
        const std::complex<double> l = leaf.eigenvalues()[i];
        out.reduced.push_back(l);
        largest = std::max(largest, std::abs(l));
        growth = std::max(growth, std::abs(l.real()));
    }
    // The eigensolver's backward error is a few ulp of ‖J‖; a double eigenvalue (at a critical
    // spin) splits by its square root, which 1e-7 leaves on the unstable side only beyond it.
    out.verdict = growth <= 1e-7 * (1 + largest) ? "spectrally stable" : "unstable";
    return out;
}

std::optional<SleepingCriterion> sleeping_criterion(const model::Model& model, int sign) {
    const model::RigidBody& body = *model.rigid;
    if (!body.principal || !(body.inertia(0, 0) - body.inertia(1, 1)).expand().is_zero() ||
        !body.center[0].is_zero() || !body.center[1].is_zero() || body.center[2].is_zero() ||
        !body.gyrostat[0].is_zero() || !body.gyrostat[1].is_zero())
        return std::nullopt;
    SleepingCriterion c;
    c.sign = sign;
    std::string spin_name = "r0";
    for (const auto& p : model.parameters)
        if (p.name == spin_name) spin_name = "r0_spin";
    c.spin = GiNaC::symbol(spin_name);
    c.lambda = GiNaC::symbol("lambda");
    const EulerPoisson s = euler_poisson(body);
    std::array<GiNaC::symbol, 6> x{body.omega[0], body.omega[1], body.omega[2],
                                   body.gamma[0], body.gamma[1], body.gamma[2]};
    std::array<ex, 6> f{s.omega_rate[0], s.omega_rate[1], s.omega_rate[2],
                        s.gamma_rate[0], s.gamma_rate[1], s.gamma_rate[2]};
    GiNaC::exmap at{{body.omega[0], 0}, {body.omega[1], 0}, {body.omega[2], c.spin},
                    {body.gamma[0], 0}, {body.gamma[1], 0}, {body.gamma[2], sign}};
    GiNaC::matrix J(6, 6);
    for (unsigned i = 0; i < 6; ++i)
        for (unsigned j = 0; j < 6; ++j) J(i, j) = derivative(f[i], x[j]).subs(at);
    // det(λ − J): GiNaC's charpoly is det(λ·1 − J).
    const ex lam = c.lambda;
    ex chi = GiNaC::normal(J.charpoly(lam));
    chi = GiNaC::numer(chi).expand();
    // Two zero eigenvalues: the Casimirs' directions (here δr and δγ3, whose rows vanish).
    GiNaC::ex rest;
    if (!GiNaC::divide(chi, GiNaC::pow(lam, 2), rest)) return std::nullopt;
    rest = rest.expand();
    if (rest.degree(lam) != 4 || !rest.coeff(lam, 1).is_zero() || !rest.coeff(lam, 3).is_zero()) return std::nullopt;
    const ex a = rest.coeff(lam, 4), b = rest.coeff(lam, 2), c0 = rest.coeff(lam, 0);
    // Collected in λ, each coefficient factored.
    for (int k = 0; k <= 4; k += 2)
        c.quartic += GiNaC::factor(GiNaC::normal(rest.coeff(lam, k) / a)) * GiNaC::pow(lam, k);
    const ex qa = 1, qb = GiNaC::normal(b / a), qc = GiNaC::normal(c0 / a);
    c.discriminant = GiNaC::normal(qb * qb - 4 * qa * qc);
    // The discriminant's factors: numbers, even powers and the moments of inertia (positive)
    // do not decide its sign; what is left does.
    const ex factored = GiNaC::factor(GiNaC::numer(c.discriminant)) / GiNaC::factor(GiNaC::denom(c.discriminant));
    std::vector<ex> positive{body.inertia(0, 0), body.inertia(2, 2)};
    ex criterion = 1;
    GiNaC::numeric sign_of = 1;
    auto take = [&](const ex& factor) {
        ex base = factor;
        ex exponent = 1;
        if (GiNaC::is_a<GiNaC::power>(factor)) {
            base = factor.op(0);
            exponent = factor.op(1);
        }
        if (GiNaC::is_a<GiNaC::numeric>(base)) {
            if (GiNaC::ex_to<GiNaC::numeric>(base).is_negative() && exponent.info(GiNaC::info_flags::odd))
                sign_of = -sign_of;
            return;
        }
        if (exponent.info(GiNaC::info_flags::even)) return;
        for (const auto& p : positive)
            if ((base - p).expand().is_zero()) return;
        criterion *= base;
    };
    if (GiNaC::is_a<GiNaC::mul>(factored))
        for (std::size_t i = 0; i < factored.nops(); ++i) take(factored.op(i));
    else
        take(factored);
    c.criterion = (sign_of * criterion).expand();
    // r0² α + β = 0: the critical spin √(−β/α) when it is real.
    const ex crit = c.criterion;
    if (crit.degree(c.spin) == 2 && crit.coeff(c.spin, 1).is_zero()) {
        const ex alpha = crit.coeff(c.spin, 2), beta = crit.coeff(c.spin, 0);
        // √(−β/α), the square root taken of numerator and denominator apart (2√(A P z0)/C).
        const ex ratio = GiNaC::normal(-beta / alpha);
        const ex num = GiNaC::numer(ratio), den = GiNaC::denom(ratio);
        const ex root_den = GiNaC::is_a<GiNaC::power>(den) && den.op(1).is_equal(2) ? den.op(0) : GiNaC::sqrt(den);
        // None where −β/α ≤ 0 at the defaults (the criterion then holds at every spin).
        const ex at_defaults = GiNaC::evalf(ratio.subs(model.parameter_defaults()));
        if (GiNaC::is_a<GiNaC::numeric>(at_defaults) && GiNaC::ex_to<GiNaC::numeric>(at_defaults).is_real() &&
            GiNaC::ex_to<GiNaC::numeric>(at_defaults).is_positive())
            c.critical_spin = GiNaC::sqrt(num) / root_den;
    }
    return c;
}

RigidEquilibria rigid_equilibria(const model::Model& model, std::optional<double> spin) {
    if (!model.rigid) throw std::logic_error("rigid_equilibria: not a rigid-body model");
    const model::RigidBody& body = *model.rigid;
    RigidEquilibria out;
    const Vec3 g = body.gamma_vector();
    const Vec3 Ig = times(body.inertia, g);
    auto det3 = [&](const Vec3& u, const Vec3& v) { return dot(g, cross(u, v)); };
    out.gyrostat = !(body.gyrostat[0].is_zero() && body.gyrostat[1].is_zero() && body.gyrostat[2].is_zero());
    if (!out.gyrostat) {
        out.cone = det3(Ig, body.center).expand();
        const Vec3 a = cross(g, Ig), c = cross(g, body.center);
        out.spin_on_cone = GiNaC::factor(GiNaC::normal(body.weight * dot(c, a) / dot(a, a)));
    } else {
        const ex d1 = det3(Ig, body.center), d2 = det3(body.center, body.gyrostat), d3 = det3(Ig, body.gyrostat);
        out.cone = (body.weight * d1 * d1 - d2 * d3).expand();
        out.spin_on_cone = GiNaC::factor(GiNaC::normal(body.weight * d1 / d3));
    }

    const D3 w0 = body.omega0;
    D3 g0 = body.vertical0;
    const double gn = norm3(g0);
    for (auto& v : g0) v /= gn;
    out.spin = spin ? *spin : dot3(w0, g0);

    // The principal axes: the body axes when I is diagonal, else I's eigenvectors at the defaults.
    const Numbers n = numbers_of(model);
    std::array<D3, 3> axes{};
    if (body.principal) {
        axes = {D3{1, 0, 0}, D3{0, 1, 0}, D3{0, 0, 1}};
    } else {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(n.I);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) axes[std::size_t(i)][std::size_t(j)] = eig.eigenvectors()(j, i);
    }
    const double tol = 1e-12;
    for (int i = 0; i < 3; ++i)
        for (int sign : {1, -1}) {
            D3 e = axes[std::size_t(i)];
            for (auto& v : e) v = v * sign + 0.0;  // no −0 printed
            // Ω γ × k = P γ × r_c on the axis (γ × Iγ = 0).
            const D3 b = cross3(e, n.k), cr = cross3(e, n.rc);
            const D3 c{n.P * cr[0], n.P * cr[1], n.P * cr[2]};
            const double scale = norm3(n.k) + std::abs(n.P) * norm3(n.rc) + 1e-300;
            PermanentRotation r;
            if (norm3(b) <= tol * scale) {
                if (norm3(c) > tol * scale) continue;
                r = linearise_rotation(model, e, out.spin);
                r.any_spin = true;
            } else {
                const double W = dot3(b, c) / dot3(b, b);
                const D3 miss{W * b[0] - c[0], W * b[1] - c[1], W * b[2] - c[2]};
                if (norm3(miss) > 1e-10 * scale) continue;
                r = linearise_rotation(model, e, W);
            }
            r.label = body.principal ? axis_label(i, sign) : fmt_axis(i, sign);
            out.rotations.push_back(r);
        }

    // The initial state: ω0 ∥ γ0 and (S) holding.
    const double W0 = dot3(w0, g0);
    const D3 across{w0[0] - W0 * g0[0], w0[1] - W0 * g0[1], w0[2] - W0 * g0[2]};
    const double wn = norm3(w0) + 1e-300;
    if (norm3(across) > 1e-10 * wn && norm3(w0) > 0) {
        out.initial_note = "the initial ω is not along the vertical (ω0 − (ω0·γ0) γ0 ≠ 0)";
    } else {
        const D3 wv{W0 * g0[0], W0 * g0[1], W0 * g0[2]};
        const double res = norm3(forcing(n, wv, g0));
        if (res > 1e-10 * forcing_scale(n, wv, g0)) {
            out.initial_note = "ω0 = Ω γ0, but (Iω0 + k) × ω0 + P γ0 × r_c ≠ 0 (the vertical is off Staude's cone or Ω "
                               "is not its spin)";
        } else {
            out.initial = linearise_rotation(model, g0, W0);
            out.initial->label = "initial state";
        }
    }
    for (int sign : {1, -1})
        if (auto c = sleeping_criterion(model, sign)) out.lagrange.push_back(*c);
    return out;
}

}  // namespace eomc::mechanics::rigid
