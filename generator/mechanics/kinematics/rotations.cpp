#include "mechanics/kinematics/rotations.hpp"

#include <vector>

#include "mechanics/kinematics/operators.hpp"
#include "symbolic/vector3.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;
using GiNaC::ex;

namespace {

// Elementary rotation about a body axis by `angle`: carrier components = R · body components.
GiNaC::matrix elementary_rotation(char axis, const ex& angle) {
    const ex c = GiNaC::cos(angle), s = GiNaC::sin(angle);
    switch (axis) {
        case 'x': return GiNaC::matrix(3, 3, GiNaC::lst{1, 0, 0, 0, c, -s, 0, s, c});
        case 'y': return GiNaC::matrix(3, 3, GiNaC::lst{c, 0, s, 0, 1, 0, -s, 0, c});
        default: return GiNaC::matrix(3, 3, GiNaC::lst{c, -s, 0, s, c, 0, 0, 0, 1});
    }
}

}  // namespace

// The relative angular velocity chain-wise, Σ_k (R_{k+1} … R_m)ᵀ θ̇_k e_k: each angle's rate
// about its own axis, carried into the final body axes (no simplification of RᵀṘ needed).
BodyRotation body_rotation(const model::Model& model, const model::Particle& body) {
    BodyRotation out{GiNaC::ex_to<GiNaC::matrix>(GiNaC::unit_matrix(3)), {0, 0, 0}};
    std::vector<GiNaC::matrix> R;
    for (const auto& [axis, angle] : body.orientation) {
        R.push_back(elementary_rotation(axis, angle));
        out.R = out.R.mul(R.back());
    }
    for (std::size_t k = 0; k < R.size(); ++k) {
        const auto& [axis, angle] = body.orientation[k];
        const ex rate = total_derivative(model, angle);  // the angle depends on q and t only
        Vec3 term{axis == 'x' ? rate : 0, axis == 'y' ? rate : 0, axis == 'z' ? rate : 0};
        for (std::size_t j = k + 1; j < R.size(); ++j) term = transpose_times(R[j], term);
        out.relative_angular_velocity = out.relative_angular_velocity + term;
    }
    return out;
}

}  // namespace eomc::mechanics
