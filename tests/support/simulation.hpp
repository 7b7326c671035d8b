// The request eomc simulate takes for a kernel built from scene text, its compiled kernels
// cached inside the build tree (never the user's ~/.cache), no progress line. Needs eomc_host.
#pragma once

#include <string>

#include "host/simulate.hpp"
#include "scenes.hpp"

namespace test_support {

inline const std::string test_cache_dir = EOMC_BINARY_DIR "/test-cache";

inline eomc::host::SimulationRequest simulation_request(const Kernel& k, double t_end) {
    eomc::host::SimulationRequest r;
    r.header_text = k.header;
    r.struct_name = k.struct_name;
    r.t_end = t_end;
    r.cache_dir = test_cache_dir;
    r.progress = false;
    return r;
}

}  // namespace test_support
