// Scenes of Mei ch. 3 that several tests drive: the closed forms are worked out once, beside the
// scene, and the tests at each stage (mechanics: λ symbolically; host: λ along a run) check them.
#pragma once

#include <array>
#include <cstddef>
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

// A free body I = (2, 3, 5) at rest, turned 0.6 rad about the space x axis (scenes/attitude_slew.toml),
// with three Erugin programs (α = 1, β = 2) err1..err3 on the given `rows` and program i driven by
// the torque about body axis axes[i]. `parameters` are the [parameters] lines.
inline std::string attitude_scene(const std::string& name, const std::string& parameters,
                                  const std::array<std::string, 3>& rows, const std::array<std::size_t, 3>& axes = {0, 1, 2}) {
    std::string toml = "[scene]\nname = \"" + name + "\"\n[parameters]\n" + parameters + R"toml([rigid_body]
inertia = ["2", "3", "5"]
weight = "0"
formulation = "quaternion"
[rigid_body.initial]
omega = [0.0, 0.0, 0.0]
attitude = { zxz = [0.0, 0.6, 0.0] }
)toml";
    const char* moments[3] = {"[1, 0, 0]", "[0, 1, 0]", "[0, 0, 1]"};
    for (std::size_t i = 0; i < 3; ++i)
        toml += "[[program]]\nname = \"err" + std::to_string(i + 1) + "\"\nconstraint = \"" + rows[i] +
                "\"\nerugin = { alpha = 1.0, beta = 2.0 }\ncontrol = { moment = " + moments[axes[i]] + " }\n";
    return toml;
}

// The rows of the attitude slew to a turn `angle` about the space z axis: the vector part of the
// error quaternion q_d* ⊗ e, q_d = (cos(angle/2), 0, 0, sin(angle/2)).
inline std::array<std::string, 3> slew_rows(const std::string& angle) {
    const std::string c = "cos((" + angle + ")/2)", s = "sin((" + angle + ")/2)";
    return {c + "*e1 + " + s + "*e2", c + "*e2 - " + s + "*e1", c + "*e3 - " + s + "*e0"};
}

}  // namespace test_support
