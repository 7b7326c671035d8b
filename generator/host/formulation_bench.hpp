// The formulation axis of `eomc bench`, shared by orbit scenes (host/orbit_bench) and rigid-body
// scenes (host/rigid_bench): one kernel per formulation, the reference formulation's as the
// request's own, and the formulations that refuse the scene left out with the reason.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/bench.hpp"
#include "host/pipeline.hpp"
#include "support/diagnostic.hpp"

namespace eomc::host {

// One family of formulations (the orbit's, the rigid body's).
struct FormulationFamily {
    std::span<const std::string_view> names;   // every formulation the generator builds: the default
    std::string FrontEndOptions::*option;      // the front end's option that picks one
    void (*check)(const std::string& name, const SourcePos& where);  // InputError for an unknown name
};

// Fills r's kernel (that of r.axis.reference, which also gives r's struct name and the scene's
// name) and r.formulations for the scene at scene_path. `asked` is --formulations (empty: every
// built formulation; then one that refuses the scene is left out with the reason in r.skipped),
// `single` is --orbit-formulation or --rigid-formulation (one name). Names are checked before
// anything is generated. Returns the reference formulation's pipeline.
Pipeline add_formulations(BenchRequest& r, const std::string& scene_path, const FormulationFamily& family,
                          const std::vector<std::string>& asked, const std::string& single);

}  // namespace eomc::host
