// Stage 3: the equations of motion of a model, by the chapter its kind belongs to. Every
// chapter returns the same Equations record, so lowering and the kernel need nothing new.
#pragma once

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// Throws InputError when the equations do not determine the accelerations (M singular),
// naming the coordinates involved.
Equations derive(const model::Model& model);

}  // namespace eomc::mechanics
