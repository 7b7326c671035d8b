// What `eomc bench` would generate for the hand-written kernel: the closed-form circular orbit.
#pragma once

#include "kernel.hpp"

namespace eomc::bench {

using Model = eomc::models::CircularKepler;
inline constexpr bool autonomous = true;
inline constexpr bool has_reference = true;
inline constexpr const char* reference_source = "tests/bench/driver/bench_config.hpp";

template <class S>
void reference(S t, S* out, const Model::Parameters& p) {
    (void)p;
    using std::cos;
    using std::sin;
    out[0] = cos(t);
    out[1] = sin(t);
    out[2] = -sin(t);
    out[3] = cos(t);
}

}  // namespace eomc::bench
