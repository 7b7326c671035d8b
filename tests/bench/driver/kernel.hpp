// A hand-written kernel in the shape eomc emits, plus the acceleration() that kernels of
// separable systems carry: the planar Kepler problem (mu = 1) in Cartesian coordinates, on the
// circular orbit r = 1 (speed 1), whose solution is known in closed form at every t. It lets the
// tests compile and run the benchmark driver (templates/bench_driver.cpp) with every method,
// the splitting ones included, independently of the generator.
#pragma once

#include <array>
#include <cmath>

namespace eomc::models {

struct CircularKepler {
    static constexpr int n_coordinates = 2;
    static constexpr int n_state = 4;
    static constexpr int n_parameters = 1;
    static constexpr int n_invariants = 2;
    static constexpr const char* scene_name = "circular_kepler";
    static constexpr std::array<const char*, n_state> state_names{"x", "y", "x_dot", "y_dot"};
    static constexpr std::array<const char*, n_parameters> parameter_names{"mu"};
    static constexpr std::array<const char*, n_invariants> invariant_names{"energy", "angular_momentum"};
    static constexpr std::array<double, n_state> initial_state{1, 0, 0, 1};

    struct Parameters {
        double mu = 1;
    };

    template <class S>
    static void acceleration(S t, const S* q, S* a, const Parameters& p) {
        (void)t;
        using std::sqrt;
        const S r2 = q[0] * q[0] + q[1] * q[1];
        const S k = -S(p.mu) / (r2 * sqrt(r2));
        a[0] = k * q[0];
        a[1] = k * q[1];
    }

    template <class S>
    static void rhs(S t, const S* x, S* dxdt, const Parameters& p) {
        dxdt[0] = x[2];
        dxdt[1] = x[3];
        acceleration(t, x, dxdt + 2, p);
    }

    template <class S>
    static void invariants(S t, const S* x, S* out, const Parameters& p) {
        (void)t;
        using std::sqrt;
        out[0] = (x[2] * x[2] + x[3] * x[3]) / S(2) - S(p.mu) / sqrt(x[0] * x[0] + x[1] * x[1]);
        out[1] = x[0] * x[3] - x[1] * x[2];
    }
};

}  // namespace eomc::models
