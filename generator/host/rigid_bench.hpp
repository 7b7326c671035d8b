// `eomc bench` on a rigid-body scene: the formulation axis. Every formulation's kernel is judged by
// ω and γ (in body axes) at t_end against a float128 run of Euler–Poisson's, whose state they are
// (the others' outputs p, q, r, gamma1..3), and by the drift of its energy integral.
#pragma once

#include <string>
#include <vector>

#include "host/bench.hpp"

namespace eomc::host {

// Fills r's Euler–Poisson kernel, its axis and formulations for the [rigid_body] scene at
// scene_path. `asked` is --formulations (empty: every built formulation; then one that refuses the
// scene, Euler angles at gimbal lock say, is left out with the reason in r.skipped),
// `rigid_formulation` is --rigid-formulation (one name). Names are checked before anything is
// generated.
void add_rigid_formulations(BenchRequest& r, const std::string& scene_path, const std::vector<std::string>& asked,
                            const std::string& rigid_formulation);

}  // namespace eomc::host
