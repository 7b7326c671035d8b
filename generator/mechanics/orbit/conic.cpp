#include "mechanics/orbit/conic.hpp"

#include "model/kepler_function.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

Conic conic(const ex& mu, const ex& a, const ex& e, const ex& ci, const ex& si, const ex& raan, const ex& argp,
            const ex& M) {
    Conic k{mu, a, e, ci, si, raan, argp, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
    k.n = GiNaC::sqrt(mu / GiNaC::pow(a, 3));
    k.eta = GiNaC::sqrt(1 - e * e);
    k.p = a * (1 - e * e);
    k.h = GiNaC::sqrt(mu * k.p);
    k.E = model::kepler_E(M, e);
    const ex cE = GiNaC::cos(k.E), sE = GiNaC::sin(k.E);
    k.r = a * (1 - e * cE);
    k.cos_nu = (cE - e) / (1 - e * cE);
    k.sin_nu = k.eta * sE / (1 - e * cE);
    const ex cO = GiNaC::cos(raan), sO = GiNaC::sin(raan), cw = GiNaC::cos(argp), sw = GiNaC::sin(argp);
    const Vec P{cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si};
    const Vec Q{-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si};
    k.normal = {sO * si, -cO * si, ci};
    for (std::size_t j = 0; j < 3; ++j) {
        k.X[j] = a * (cE - e) * P[j] + a * k.eta * sE * Q[j];
        k.V[j] = k.n * a * a / k.r * (-sE * P[j] + k.eta * cE * Q[j]);
        k.radial[j] = k.cos_nu * P[j] + k.sin_nu * Q[j];
        k.transverse[j] = -k.sin_nu * P[j] + k.cos_nu * Q[j];
    }
    return k;
}

}  // namespace eomc::mechanics
