// rhs per call of one checked-in kernel as `eomc simulate` loads it, compiled for the host
// (-march=native) against the portable build (EOMC_PORTABLE=1), both loaded in one process and
// called through the C interface; and the SIMD batch (4 members per call, --batch) the same two
// ways, per member. Paired (bench/paired_timing.hpp): medians and the median per-pair ratio.
//
//   build/bench/bench_kernel_target_timing SCENE STRUCT     e.g. leo_j2 LeoJ2   (from the repository root)
// Prints `key value` lines; compiles into a temporary cache, removed afterwards.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "host/kernel_loader.hpp"
#include "paired_timing.hpp"

using eomc::host::KernelLibrary;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SCENE STRUCT   (generated/SCENE.hpp, eomc::models::STRUCT)\n", argv[0]);
        return 2;
    }
    std::ifstream in(std::string("generated/") + argv[1] + ".hpp");
    std::stringstream text;
    text << in.rdbuf();
    if (!in) {
        std::fprintf(stderr, "cannot read generated/%s.hpp (run from the repository root)\n", argv[1]);
        return 2;
    }
    const eomc::host::TempDir cache("eomc-target-timing-");
    const auto load = [&](bool portable, bool batch) {
        if (portable) ::setenv("EOMC_PORTABLE", "1", 1);
        KernelLibrary lib = KernelLibrary::load(text.str(), argv[2], cache.path().string(), batch);
        ::unsetenv("EOMC_PORTABLE");
        return lib;
    };
    const KernelLibrary native = load(false, true), portable = load(true, true);
    const std::size_t n = native.initial_state().size(), lanes = std::size_t(native.batch_width());

    // States near the initial one, as bench/solve_timing.cpp draws them.
    std::mt19937_64 rng(20261126);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    constexpr int states = 256;
    std::vector<double> x(states * n), dx(n * (lanes ? lanes : 1));
    for (int b = 0; b < states; ++b)
        for (std::size_t i = 0; i < n; ++i) {
            const double v = u(rng);
            x[b * n + i] = native.initial_state()[i] * (1 + v / 5) + v / 5;
        }
    const auto pn = native.make_parameters(native.parameter_defaults());
    const auto pp = portable.make_parameters(portable.parameter_defaults());
    double checksum = 0;
    const auto sweep = [&](const KernelLibrary& lib, const KernelLibrary::Parameters& p) {
        for (int b = 0; b < states; ++b) {
            lib.rhs(0.0, &x[b * n], dx.data(), p);
            checksum += dx[n - 1];
        }
    };
    const bench::PairedTiming t =
        bench::time_paired([&] { sweep(native, pn); }, [&] { sweep(portable, pp); }, states);
    std::printf("native_rhs_ns %.2f\nportable_rhs_ns %.2f\nportable_over_native %.3f\n", t.first_median * 1e9,
                t.second_median * 1e9, 1 / t.ratio);
    if (lanes > 0) {
        // Lane-minor batches of `lanes` consecutive states, per member.
        std::vector<double> batched(states * n);
        for (int b = 0; b < states; b += int(lanes))
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t k = 0; k < lanes; ++k) batched[b * n + i * lanes + k] = x[(b + k) * n + i];
        std::vector<double> values;
        for (std::size_t j = 0; j < native.parameter_defaults().size(); ++j)
            for (std::size_t k = 0; k < lanes; ++k) values.push_back(native.parameter_defaults()[j]);
        const auto bn = native.make_batch_parameters(values), bp = portable.make_batch_parameters(values);
        const auto batch_sweep = [&](const KernelLibrary& lib, const KernelLibrary::Parameters& p) {
            for (int b = 0; b < states; b += int(lanes)) {
                lib.rhs_batch(0.0, &batched[b * n], dx.data(), p);
                checksum += dx[0];
            }
        };
        const bench::PairedTiming tb =
            bench::time_paired([&] { batch_sweep(native, bn); }, [&] { batch_sweep(portable, bp); }, states);
        std::printf("native_batch_ns_per_member %.2f\nportable_batch_ns_per_member %.2f\nbatch_portable_over_native %.3f\n",
                    tb.first_median * 1e9, tb.second_median * 1e9, 1 / tb.ratio);
    }
    std::printf("checksum %.6e\n", checksum);
}
