// Scenes of Mei ch. 3 that several tests drive: the closed forms are worked out once, beside the
// scene, and the tests at each stage (mechanics: λ symbolically; host: λ along a run) check them.
#pragma once

#include <string>

namespace test_support {

// A bead of mass m on the fixed vertical circle x² + y² = R² (a [[constraint]] row, Baumgarte
// α = 1, β = 2; gravity m g along −y), kept at speed v0 by a tangential control d = (−y, x) on
// the program φ = (ẋ² + ẏ² − v0²)/2, Erugin's κ = 3. On the programmed motion (f = ḟ = φ = 0),
// tangentially m v̇ = 0 = −m g x/R + λ R, so the control λ = m g x/R²; radially
// −m v0²/R = −m g y/R + 2R μ, so the reaction μ = m (g y − v0²)/(2R²). m = R = 1, g = 9.81, v0 = 3,
// starting at the bottom moving right.
inline std::string bead_on_circle_at_constant_speed() {
    return R"toml([scene]
name = "bead_on_circle"
[parameters]
m = 1.0
g = 9.81
R = 1.0
v0 = 3.0
[coordinates]
x = { initial = 0.0, rate = 3.0 }
y = { initial = -1.0, rate = 0.0 }
[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"
[[constraint]]
name = "circle"
holonomic = "x^2 + y^2 - R^2"
stabilize = { alpha = 1, beta = 2 }
[[program]]
name = "speed"
constraint = "(x_dot^2 + y_dot^2 - v0^2)/2"
erugin = { kappa = 3 }
control = { x = "-y", y = "x" }
)toml";
}

}  // namespace test_support
