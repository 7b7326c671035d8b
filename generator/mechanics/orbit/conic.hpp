// The Kepler orbit of classical elements as expressions, for the formulations that write the
// Cartesian state in elements (element_formulations, encke's reference ellipse): E =
// kepler_E(M, e), r = a(1 − e cos E), the perifocal unit vectors P, Q and the orbit normal W,
// the position, the velocity, and the radial and transverse unit vectors (Vallado,
// Fundamentals of Astrodynamics, 4th ed., §2.6). The inclination enters by its cosine and sine
// (the Delaunay form has cos i = H/G).
#pragma once

#include <array>

#include <ginac/ginac.h>

namespace eomc::mechanics {

using Vec = std::array<GiNaC::ex, 3>;

struct Conic {
    GiNaC::ex mu, a, e, ci, si, raan, argp;
    GiNaC::ex n, eta, p, h;  // mean motion, √(1 − e²), semi-latus rectum, specific angular momentum √(μp)
    GiNaC::ex E, r, cos_nu, sin_nu;
    Vec X, V, radial, transverse, normal;
};

Conic conic(const GiNaC::ex& mu, const GiNaC::ex& a, const GiNaC::ex& e, const GiNaC::ex& ci, const GiNaC::ex& si,
            const GiNaC::ex& raan, const GiNaC::ex& argp, const GiNaC::ex& M);

}  // namespace eomc::mechanics
