// Two pieces of code timed against each other on a shared machine (bench/rhs_timing.cpp,
// bench/solve_timing.cpp). Each sample runs one side for about 1 ms, then the other; 301 pairs.
// The load changes between samples, so the fairest figure is the median of the per-pair ratio
// (both sides under the same load); the medians and minima per call are kept as well.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace bench {

struct PairedTiming {
    double first_median, second_median;  // seconds per call
    double first_min, second_min;
    double ratio;  // median over the pairs of first / second
};

template <class F>
double seconds_of(F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// `first` and `second` each make `calls` calls (a sweep over a batch of states).
template <class First, class Second>
PairedTiming time_paired(First&& first, Second&& second, int calls, int pairs = 301) {
    const double one = std::max(seconds_of(first), seconds_of(second));
    const int sweeps = std::max(1, int(1e-3 / std::max(one, 1e-9)));
    std::vector<double> a, b, ratio;
    for (int r = 0; r < pairs; ++r) {
        a.push_back(seconds_of([&] { for (int s = 0; s < sweeps; ++s) first(); }) / (sweeps * calls));
        b.push_back(seconds_of([&] { for (int s = 0; s < sweeps; ++s) second(); }) / (sweeps * calls));
        ratio.push_back(a.back() / b.back());
    }
    return {median(a), median(b), *std::min_element(a.begin(), a.end()), *std::min_element(b.begin(), b.end()),
            median(ratio)};
}

}  // namespace bench
