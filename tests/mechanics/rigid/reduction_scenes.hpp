// The scenes of the reduction tests, as TOML text.
#pragma once

#include <string>

namespace rigid_scenes {

// The heavy symmetric top in Euler angles (ZXZ: φ precession, θ nutation, ψ spin).
inline std::string top(const std::string& theta = "0.6", const std::string& phi_dot = "1.0",
                       const std::string& psi_dot = "20.0") {
    return R"toml([scene]
name = "heavy_top"
summary = "Heavy symmetric top in Euler angles"

[parameters]
A = 2.0
C = 1.0
P = 9.81
z0 = 0.5

[coordinates]
phi = { initial = 0.0, rate = )toml" + phi_dot + R"toml( }
theta = { initial = )toml" + theta + R"toml(, rate = 0.0 }
psi = { initial = 0.0, rate = )toml" + psi_dot + R"toml( }

[lagrangian]
T = "A/2*(theta_dot^2 + phi_dot^2*sin(theta)^2) + C/2*(psi_dot + phi_dot*cos(theta))^2"
V = "P*z0*cos(theta)"

[simulate]
t_end = 2.0
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12
)toml";
}

// Planar Kepler motion in polar coordinates.
inline const char* kepler_polar = R"toml([scene]
name = "kepler_polar"

[parameters]
mu = 1.0

[coordinates]
r = { initial = 0.5, rate = 0.0 }
theta = { initial = 0.0, rate = 3.4641016151377544 }

[lagrangian]
T = "(r_dot^2 + r^2*theta_dot^2)/2"
V = "-mu/r"
)toml";

// A damped oscillator given by its energies and the force Q = −c q̇.
inline const char* damped = R"toml([scene]
name = "damped"

[parameters]
m = 1.5
k = 2.0
c = 0.3

[coordinates]
x = { initial = 1.0, rate = 0.0 }

[lagrangian]
T = "m*x_dot^2/2"
V = "k*x^2/2"

[forces]
generalized = { x = "-c*x_dot" }
)toml";

}  // namespace rigid_scenes
