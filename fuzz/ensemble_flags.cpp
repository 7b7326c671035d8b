// libFuzzer target: any bytes as the flags of `eomc sweep` or `eomc ensemble`, one a line —
// `--grid TEXT`, `--vary TEXT`, `--observe TEXT`, `--samples TEXT`, `--seed TEXT` (other lines are
// skipped) — read the way the command reads them (cli/options.cpp's ensemble_spec, then
// host::check_names and host::BoundObservations against a fixed kernel's names). A refusal must be
// an InputError. What the command does with an accepted specification must not throw at all: a few
// members' inputs are drawn and each observation is evaluated at two fixed states. Anything else —
// a crash, undefined behaviour, another exception, a hang, unbounded memory — is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "host/ensemble_spec.hpp"
#include "host/observation.hpp"
#include "support/diagnostic.hpp"

namespace {

// The kernel the flags are checked against: the names of the seeds (tests, docs) and a few more.
const std::vector<std::string> parameters{"w", "omega", "g", "R", "k", "m", "l", "C", "Cd", "CdA_m", "gamma", "spin", "a", "b"};
const std::vector<std::string> states{"theta", "q", "x", "z0", "theta_dot", "q_dot", "x_dot", "z0_dot"};
const std::vector<std::string> events{"re_entry", "impact"};

// A member's inputs: a grid point between its axis's ends, a uniform draw in [a, b], and no NaN.
void check_inputs(const eomc::host::EnsembleSpec& spec, std::size_t index) {
    const std::vector<double> x = spec.inputs(index);
    const auto finding = [&](std::size_t k, const char* what) {
        std::fprintf(stderr, "member %zu: input %zu = %.17g %s\n", index, k, x[k], what);
        std::abort();
    };
    for (std::size_t k = 0; k < spec.grid.size(); ++k)
        if (!(x[k] >= spec.grid[k].first && x[k] <= spec.grid[k].last)) finding(k, "is not between the grid's ends");
    for (std::size_t k = 0; k < spec.vary.size(); ++k) {
        const double v = x[spec.grid.size() + k];
        const auto& d = spec.vary[k];
        if (std::isnan(v)) finding(spec.grid.size() + k, "is not a number");
        if (d.kind == eomc::host::Distribution::uniform && !(v >= d.a && v <= d.b))
            finding(spec.grid.size() + k, "is not in the uniform distribution's range");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> grid, vary, observe;
    std::string samples = "100", seed = "0";  // the command's defaults
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view line = text.substr(start, end - start);
        start = end + 1;
        const std::size_t space = line.find(' ');
        if (space == std::string_view::npos) continue;
        const std::string_view flag = line.substr(0, space);
        const std::string value(line.substr(space + 1));
        if (flag == "--grid") grid.push_back(value);
        else if (flag == "--vary") vary.push_back(value);
        else if (flag == "--observe") observe.push_back(value);
        else if (flag == "--samples") samples = value;
        else if (flag == "--seed") seed = value;
    }

    eomc::host::EnsembleSpec spec;
    eomc::host::BoundObservations bound;
    try {
        // cli::ensemble_spec, then the checks against the kernel (cli/main.cpp, host/ensemble.cpp).
        for (const auto& g : grid) spec.grid.push_back(eomc::host::parse_grid(g));
        for (const auto& v : vary) spec.vary.push_back(eomc::host::parse_variation(v));
        if (!vary.empty()) {
            spec.samples = eomc::host::parse_samples(samples);
            spec.seed = eomc::host::parse_seed(seed);
        }
        (void)spec.members();
        eomc::host::check_names(spec, parameters, states, {{"l", 1.0}});
        std::vector<eomc::host::Observation> observations;
        for (const auto& o : observe) observations.push_back(eomc::host::parse_observation(o));
        std::vector<std::string> taken{"member", "status", "t", "events", "message", "E_max_drift"};
        for (const auto& names : {spec.input_names(), states}) taken.insert(taken.end(), names.begin(), names.end());
        bound = eomc::host::BoundObservations(observations, parameters, states, events, taken);
    } catch (const eomc::InputError&) {
        return 0;  // a refusal at its flag: the expected outcome for most inputs
    }

    // Accepted: nothing below may throw (the ensemble runs it on every member).
    const std::size_t members = spec.members();
    for (const std::size_t i : {std::size_t{0}, members / 2, members - 1})
        if (i < members) check_inputs(spec, i);
    const double big = std::numeric_limits<double>::max(), tiny = std::numeric_limits<double>::min();
    const std::vector<std::vector<double>> points{{0.5, -1.0, 2.0, 0.0}, {big, -tiny, -big, tiny}};
    for (std::size_t i = 0; i < bound.size(); ++i)
        for (const auto& x : points) {
            std::vector<double> p(parameters.size()), s(states.size());
            for (std::size_t k = 0; k < p.size(); ++k) p[k] = x[k % x.size()];
            for (std::size_t k = 0; k < s.size(); ++k) s[k] = x[(k + 1) % x.size()];
            (void)bound.evaluate(i, x[2], p, s);
        }
    return 0;
}
