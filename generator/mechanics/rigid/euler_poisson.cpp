#include "mechanics/rigid/euler_poisson.hpp"

#include <algorithm>
#include <stdexcept>

#include "mechanics/rigid/integrals.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/simplify.hpp"
#include "symbolic/vector3.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;
using namespace eomc::symbolic;

EulerPoisson euler_poisson(const model::RigidBody& body) {
    EulerPoisson s;
    const Vec3 w = body.omega_vector(), g = body.gamma_vector();
    s.momentum = times(body.inertia, w) + body.gyrostat;
    s.torque = body.weight * cross(g, body.center);
    s.forcing = cross(s.momentum, w) + s.torque;
    if (body.principal) {
        for (unsigned i = 0; i < 3; ++i) s.omega_rate[i] = s.forcing[i] / body.inertia(i, i);
    } else {
        // A symmetric 3×3 of parameters: its inverse is small enough to write in closed form.
        const GiNaC::matrix inverse = body.inertia.inverse();
        s.omega_rate = times(inverse, s.forcing);
        for (auto& r : s.omega_rate) r = normalized(r);
    }
    s.gamma_rate = cross(g, w);
    s.divergence = 0;
    for (unsigned i = 0; i < 3; ++i)
        s.divergence += derivative(s.omega_rate[i], body.omega[i]) + derivative(s.gamma_rate[i], body.gamma[i]);
    s.divergence = body.principal ? s.divergence.expand() : simplified(s.divergence);
    s.kinetic = dot(w, times(body.inertia, w)) / 2;
    s.potential = body.weight * dot(body.center, g);
    const Invariant candidates[] = {
        {"energy", s.kinetic + s.potential, "H = ½ ω·Iω + P r_c·γ (the field's power balance: ω·(P γ × r_c) + P r_c·(γ × ω) = 0)"},
        {"area", dot(s.momentum, g), "K·γ, the angular momentum about the vertical (gravity's moment is horizontal)"},
        {"geometric", dot(g, g), "|γ|², the vertical fixed in space"}};
    for (const auto& c : candidates)
        if (rate_along(s, body, c.value).is_zero()) s.integrals.push_back(c);
    return s;
}

ex rate_along(const EulerPoisson& s, const model::RigidBody& body, const ex& h) {
    ex rate = 0;
    for (unsigned i = 0; i < 3; ++i) {
        rate += derivative(h, body.omega[i]) * s.omega_rate[i];
        rate += derivative(h, body.gamma[i]) * s.gamma_rate[i];
    }
    return body.principal ? rate.expand() : simplified(rate);
}

}  // namespace eomc::mechanics::rigid

namespace eomc::mechanics::rigid {

void add_body_integrals_in_angles(const model::Model& model, Equations& eqs) {
    const model::RigidBody& body = *model.rigid;
    const EulerPoisson s = euler_poisson(body);
    std::vector<Invariant> carried;
    for (const auto& inv : s.integrals)
        if (inv.name == "area") carried.push_back(inv);
    for (auto& inv : tracked_invariants(search_rigid_integrals(model, s, default_search_degree))) carried.push_back(inv);
    for (const auto& inv : carried) {
        const ex value = inv.value.subs(body.in_angles);
        const auto same = std::find_if(eqs.invariants.begin(), eqs.invariants.end(),
                                       [&](const Invariant& known) { return simplified(known.value - value).is_zero(); });
        if (same == eqs.invariants.end()) eqs.invariants.push_back({inv.name, value, inv.description});
        else same->description += "; it is the " + inv.name + " integral of the Euler–Poisson equations";
    }
}

Equations derive_rigid(const model::Model& model) {
    const model::RigidBody& body = *model.rigid;
    if (body.formulation == scene::RigidFormulationKind::euler_angles)
        throw std::logic_error("derive_rigid: the euler_angles formulation is derived by Lagrange's equations");
    const EulerPoisson s = euler_poisson(body);
    Equations eqs;
    eqs.T = s.kinetic;
    eqs.V = s.potential;
    eqs.mass_matrix = body.inertia;
    const Vec3 rates{body.omega_rate[0], body.omega_rate[1], body.omega_rate[2]};
    const Vec3 inertial = times(body.inertia, rates) - cross(s.momentum, body.omega_vector());
    const Vec3 Iw = times(body.inertia, body.omega_vector());
    const char* names[3] = {"p", "q", "r"};
    for (unsigned i = 0; i < 3; ++i) {
        eqs.equations.push_back({names[i], inertial[i], s.torque[i], {}, Iw[i]});
        eqs.forcing.push_back(s.forcing[i]);
    }
    eqs.invariants = s.integrals;
    for (auto& inv : tracked_invariants(search_rigid_integrals(model, s, default_search_degree)))
        eqs.invariants.push_back(std::move(inv));
    return eqs;
}

}  // namespace eomc::mechanics::rigid
