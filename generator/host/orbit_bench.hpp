// `eomc bench` on an orbit scene: the formulation axis. Every formulation's kernel is judged by
// its position at t_end against a float128 run of Cowell's (the request's own kernel).
#pragma once

#include <string>
#include <vector>

#include "host/bench.hpp"

namespace eomc::host {

// Fills r's Cowell kernel, period and formulations for the orbit scene at scene_path. `asked`
// is --formulations (empty: every built formulation; then one that refuses the scene is left
// out with the reason in r.skipped), `orbit_formulation` is --orbit-formulation (one name).
// Names are checked before anything is generated.
void add_orbit_formulations(BenchRequest& r, const std::string& scene_path, const std::vector<std::string>& asked,
                            const std::string& orbit_formulation);

}  // namespace eomc::host
