// The exact period of the pendulum θ̈ = −w² sin θ released from rest at θ0: T = 4 K(k)/w with
// k = sin(θ0/2) and K(k) = π/(2 AGM(1, √(1 − k²))), the complete elliptic integral of the first
// kind by the arithmetic–geometric mean (quadratic convergence, exact to round-off).
#pragma once

#include <cmath>
#include <numbers>

namespace test_support {

inline double agm(double a, double b) {
    for (int i = 0; i < 64 && a != b; ++i) {
        const double m = (a + b) / 2;
        b = std::sqrt(a * b);
        a = m;
    }
    return a;
}

inline double pendulum_period(double w, double theta0) {
    const double k = std::sin(theta0 / 2);
    return 4 * (std::numbers::pi / (2 * agm(1.0, std::sqrt(1 - k * k)))) / w;
}

}  // namespace test_support
