// What an ensemble varies: `eomc sweep`'s grid (--grid NAME=a:b:n) or `eomc ensemble`'s random
// draws (--vary NAME=normal(mu,sigma) | uniform(a,b) | lognormal(mu,sigma), --samples, --seed),
// and each member's inputs from it. A member's inputs depend on the specification and its index
// alone, never on which thread or rank runs it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "support/diagnostic.hpp"

namespace eomc::host {

// n points from first to last inclusive, evenly spaced; n = 1 is the single value `first`.
struct GridAxis {
    std::string name;
    double first = 0.0, last = 0.0;
    std::size_t count = 1;
    SourcePos where;  // "--grid NAME=…", for the errors found later (an unknown name)
    double value(std::size_t i) const;
};

enum class Distribution { normal, uniform, lognormal };

// normal(mu, sigma), uniform(a, b) on [a, b), lognormal(mu, sigma) = exp(normal(mu, sigma)).
struct Variation {
    std::string name;
    Distribution kind = Distribution::normal;
    double a = 0.0, b = 0.0;  // (mu, sigma) or (a, b)
    SourcePos where;
};

struct EnsembleSpec {
    std::vector<GridAxis> grid;   // a sweep: the Cartesian product, the last axis varying fastest
    std::vector<Variation> vary;  // an ensemble: `samples` members drawn from `seed`
    std::size_t samples = 0;
    std::uint64_t seed = 0;

    // The inputs' names in column order (the grid's axes, then the varied names).
    std::vector<std::string> input_names() const;
    std::size_t members() const;
    // Member `index`'s inputs, in input_names() order.
    std::vector<double> inputs(std::size_t index) const;
};

// Each parser throws InputError at the flag with its text ("--grid k=1:0:5: …").
GridAxis parse_grid(std::string_view text);
Variation parse_variation(std::string_view text);
std::size_t parse_samples(std::string_view text);
std::uint64_t parse_seed(std::string_view text);

// Every varied name must be a parameter or a state variable (the names --set takes), given once,
// and not also by --set (`fixed`). Throws InputError at the flag, with the nearest known name.
void check_names(const EnsembleSpec& spec, const std::vector<std::string>& parameters,
                 const std::vector<std::string>& states, const std::vector<std::pair<std::string, double>>& fixed);

// The member's random stream: splitmix64 of (seed, index), so the draws are those of its index.
std::uint64_t member_seed(std::uint64_t seed, std::size_t index);

}  // namespace eomc::host
