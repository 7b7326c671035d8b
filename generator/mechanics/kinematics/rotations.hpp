// A carried rigid body's orientation as a chain of elementary rotations about body axes.
#pragma once

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics {

// A rigid body's orientation relative to the carrier, R = R_1 R_2 … R_m (carrier components =
// R · body components), and its angular velocity relative to the carrier in body axes.
struct BodyRotation {
    GiNaC::matrix R;
    model::Vec3 relative_angular_velocity;
};
BodyRotation body_rotation(const model::Model& model, const model::Particle& body);

}  // namespace eomc::mechanics
