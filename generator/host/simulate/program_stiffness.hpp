// The programs' stiffness warning (Mei ch. 3): gains that make a closed loop stiff for the chosen
// explicit integrator, judged before the run from the residual law's eigenvalues
// (mechanics::residual_eigenvalues) and the method's stability region (runtime/registry_info.hpp).
#pragma once

#include <string>
#include <vector>

#include "eomc/runtime/registry_info.hpp"
#include "model/model.hpp"

namespace eomc::host {

// One line per program whose residual, stepped by `method`, will not decay as its law says (no
// "warning:" prefix), naming the program and its gains. A fixed-step explicit method at step h: hλ
// outside its stability region |R(hλ)| ≤ 1 (RK4's ends at z ≈ −2.785 on the negative real axis),
// where the residual grows instead of decaying. An explicit adaptive method: the step-size control
// holds h|λ| near the region's real boundary b (≈ 3.3 for dopri5, ≈ 6.1 for dop853; Hairer & Wanner,
// Solving Ordinary Differential Equations II, §IV.2), so a run costs about t_end |λ| / b steps: a
// warning when that passes 10⁶. Implicit methods (A-stable, L-stable) get none.
std::vector<std::string> program_stiffness_warnings(const model::Model& model, const runtime::IntegratorInfo& method,
                                                    double step, double t_end);

}  // namespace eomc::host
