// Andoyer–Deprit canonical variables of a rigid body about a fixed point, from and to the body's
// angular momentum and upward vertical (H. Andoyer, Cours de mécanique céleste, 1923; A. Deprit,
// Am. J. Phys. 35 (1967) 424–428). With K the angular momentum and e_Z the upward vertical:
//   G = |K|,  L = K·e3 (body axis 3),  H = K·e_Z,
//   K_body = (√(G² − L²) sin l, √(G² − L²) cos l, L),
// and the body is reached from space through the node frames R_z(h) R_x(I2) R_z(g) R_x(I1) R_z(l)
// with cos I1 = L/G, cos I2 = H/G; so γ = R_z(l)ᵀ R_x(I1)ᵀ R_z(g)ᵀ (0, sin I2, cos I2). The
// variables are singular where K is along body axis 3 (L = ±G: l undefined) or along the
// vertical (H = ±G: g undefined), as the classical orbit elements are at e = 0 and i = 0.
#pragma once

#include <array>
#include <cmath>
#include <stdexcept>

namespace eomc::runtime {

struct AndoyerDeprit {
    double l, g, h, L, G, H;
};

// K (body axes) and γ (unit, body axes) → (l, g, h, L, G, H), with h = 0: a heavy body's motion
// does not depend on the node's azimuth. Throws std::domain_error at L = ±G or H = ±G (to
// `singular` of G).
inline AndoyerDeprit andoyer_from_body(const std::array<double, 3>& K, const std::array<double, 3>& gamma,
                                       double singular = 1e-12) {
    const double G = std::sqrt(K[0] * K[0] + K[1] * K[1] + K[2] * K[2]);
    if (!(G > 0)) throw std::domain_error("the angular momentum is zero: the Andoyer-Deprit variables are undefined");
    const double L = K[2];
    const double H = K[0] * gamma[0] + K[1] * gamma[1] + K[2] * gamma[2];
    const double s1 = std::sqrt(std::max(0.0, G * G - L * L)) / G, s2 = std::sqrt(std::max(0.0, G * G - H * H)) / G;
    if (s1 <= singular)
        throw std::domain_error("the angular momentum lies along body axis 3 (L = ±G): the Andoyer-Deprit angle l "
                                "is undefined there");
    if (s2 <= singular)
        throw std::domain_error("the angular momentum is vertical (H = ±G): the Andoyer-Deprit angle g is undefined "
                                "there");
    const double l = std::atan2(K[0], K[1]);
    const double c1 = L / G;
    // u = R_x(I1) R_z(l) γ = R_z(g)ᵀ (0, sin I2, cos I2) = (sin I2 sin g, sin I2 cos g, cos I2).
    const double a = std::cos(l) * gamma[0] - std::sin(l) * gamma[1];
    const double b = std::sin(l) * gamma[0] + std::cos(l) * gamma[1];
    const double u1 = a, u2 = c1 * b - s1 * gamma[2];
    return {l, std::atan2(u1, u2), 0.0, L, G, H};
}

// How close the state is to the variables' singular sets: min(√(G² − L²), √(G² − H²))/G.
inline double andoyer_regularity(const AndoyerDeprit& v) {
    const double G = std::abs(v.G);
    return std::min(std::sqrt(std::max(0.0, G * G - v.L * v.L)), std::sqrt(std::max(0.0, G * G - v.H * v.H))) / G;
}

}  // namespace eomc::runtime
