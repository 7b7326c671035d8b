#include "host/ensemble_spec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "support/decimal.hpp"

namespace eomc::host {

namespace {

// A bound on the runs one command may ask for (a mistyped 0:1:1e9 should not start).
constexpr std::size_t max_members = 100'000'000;

std::string_view trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t");
    return first == std::string_view::npos ? std::string_view{} : text.substr(first, last - first + 1);
}

// "NAME=REST" → (NAME, REST); the name must look like one (a letter or _, then letters, digits, _).
std::pair<std::string, std::string_view> name_and_value(std::string_view text, const SourcePos& where,
                                                        const char* shape) {
    const auto eq = text.find('=');
    const std::string_view name = eq == std::string_view::npos ? std::string_view{} : trimmed(text.substr(0, eq));
    if (name.empty()) throw InputError(where, fmt::format("expected {}", shape));
    const auto ok = [](char c, bool first) {
        return c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (!first && c >= '0' && c <= '9');
    };
    for (std::size_t i = 0; i < name.size(); ++i)
        if (!ok(name[i], i == 0)) throw InputError(where, fmt::format("'{}' is not a name (expected {})", name, shape));
    return {std::string(name), trimmed(text.substr(eq + 1))};
}

// A count: decimal digits only (no sign, no exponent), at most `limit`.
std::size_t parse_count(std::string_view text, const SourcePos& where, const char* what, std::size_t limit) {
    const std::string_view t = trimmed(text);
    if (!t.empty() && t.front() == '-' && t.size() > 1 && t.find_first_not_of("0123456789", 1) == std::string_view::npos)
        throw InputError(where, fmt::format("{} must be positive, not {}", what, t));
    if (t.empty() || t.find_first_not_of("0123456789") != std::string_view::npos)
        throw InputError(where, fmt::format("{} must be a whole number, not '{}'", what, t));
    if (t.find_first_not_of('0') == std::string_view::npos)
        throw InputError(where, fmt::format("{} must be at least 1, not {}", what, t));
    if (t.size() > 12 || std::stoull(std::string(t)) > limit)
        throw InputError(where, fmt::format("{} {} is more than the limit of {}", what, t, limit));
    return static_cast<std::size_t>(std::stoull(std::string(t)));
}

std::uint64_t mix(std::uint64_t z) {  // splitmix64's step (Steele, Lea, Flood 2014)
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// The draws from mt19937_64 (its output is fixed by the standard) through transforms written
// here, not std::normal_distribution, whose algorithm differs between standard libraries.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }  // [0, 1)

double standard_normal(std::mt19937_64& rng) {  // Box–Muller, the cosine branch
    const double u1 = 1.0 - uniform01(rng), u2 = uniform01(rng);  // u1 in (0, 1]
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace

double GridAxis::value(std::size_t i) const {
    if (count <= 1) return first;
    if (i + 1 >= count) return last;  // the end point exactly
    // (b − a)·i/(n − 1) keeps the points of a decimal range exact (0:12:121 gives i/10); where (b − a)·i
    // overflows (a range near double's limit: -1e308:1e3:83 gave inf from i = 2), the fraction first.
    const double span = last - first, k = static_cast<double>(i), n = static_cast<double>(count - 1);
    const double step = std::isfinite(span * k) ? span * k / n : span * (k / n);
    return std::clamp(first + step, first, last);  // rounding never steps past an end
}

GridAxis parse_grid(std::string_view text) {
    const SourcePos where{"--grid " + std::string(text)};
    auto [name, rest] = name_and_value(text, where, "NAME=a:b:n (n points from a to b) or NAME=value");
    GridAxis axis;
    axis.name = std::move(name);
    axis.where = where;
    const auto c1 = rest.find(':');
    if (c1 == std::string_view::npos) {
        axis.first = axis.last = parse_decimal(rest, where);
        return axis;
    }
    const auto c2 = rest.find(':', c1 + 1);
    if (c2 == std::string_view::npos || rest.find(':', c2 + 1) != std::string_view::npos)
        throw InputError(where, "expected NAME=a:b:n (n points from a to b) or NAME=value");
    axis.first = parse_decimal(rest.substr(0, c1), where);
    axis.last = parse_decimal(rest.substr(c1 + 1, c2 - c1 - 1), where);
    axis.count = parse_count(rest.substr(c2 + 1), where, "the number of points n", max_members);
    if (axis.count == 1 && axis.first != axis.last)
        throw InputError(where, fmt::format("a:b:1 is one point but a = {} and b = {} differ; give {}=a for a single value",
                                            axis.first, axis.last, axis.name));
    if (axis.count > 1 && axis.first == axis.last)
        throw InputError(where, fmt::format("the range {}:{} is empty ({} points between equal ends)", axis.first,
                                            axis.last, axis.count));
    if (axis.count > 1 && axis.first > axis.last)
        throw InputError(where, fmt::format("the range {}:{} is reversed (a must be below b)", axis.first, axis.last));
    if (!std::isfinite(axis.last - axis.first))
        throw InputError(where, fmt::format("the range {}:{} is wider than a double holds", axis.first, axis.last));
    return axis;
}

Variation parse_variation(std::string_view text) {
    const SourcePos where{"--vary " + std::string(text)};
    const char* shape = "NAME=normal(mu,sigma), NAME=uniform(a,b) or NAME=lognormal(mu,sigma)";
    auto [name, rest] = name_and_value(text, where, shape);
    Variation v;
    v.name = std::move(name);
    v.where = where;
    const auto open = rest.find('(');
    if (open == std::string_view::npos || rest.back() != ')') throw InputError(where, fmt::format("expected {}", shape));
    const std::string kind(trimmed(rest.substr(0, open)));
    if (kind == "normal") v.kind = Distribution::normal;
    else if (kind == "uniform") v.kind = Distribution::uniform;
    else if (kind == "lognormal") v.kind = Distribution::lognormal;
    else {
        const std::string near = nearest_name(kind, {"normal", "uniform", "lognormal"});
        throw InputError(where, fmt::format("unknown distribution '{}'{} (expected normal, uniform or lognormal)", kind,
                                            near.empty() ? "" : "; did you mean '" + near + "'?"));
    }
    const std::string_view args = rest.substr(open + 1, rest.size() - open - 2);
    const auto comma = args.find(',');
    if (comma == std::string_view::npos || args.find(',', comma + 1) != std::string_view::npos)
        throw InputError(where, fmt::format("{} takes two numbers, {}", kind,
                                            v.kind == Distribution::uniform ? "(a,b)" : "(mu,sigma)"));
    v.a = parse_decimal(args.substr(0, comma), where);
    v.b = parse_decimal(args.substr(comma + 1), where);
    if (v.kind == Distribution::uniform) {
        if (!(v.a < v.b)) throw InputError(where, fmt::format("uniform(a,b) needs a < b, not a = {}, b = {}", v.a, v.b));
        if (!std::isfinite(v.b - v.a))
            throw InputError(where, fmt::format("uniform({},{}) is wider than a double holds", v.a, v.b));
    } else if (!(v.b > 0.0)) {
        throw InputError(where, fmt::format("{}(mu,sigma) needs sigma > 0, not {}", kind, v.b));
    }
    return v;
}

std::size_t parse_samples(std::string_view text) {
    return parse_count(text, SourcePos{"--samples"}, "the sample count", max_members);
}

std::uint64_t parse_seed(std::string_view text) {
    const SourcePos where{"--seed"};
    const std::string_view t = trimmed(text);
    if (t.empty() || t.find_first_not_of("0123456789") != std::string_view::npos)
        throw InputError(where, fmt::format("the seed must be a whole number from 0 to 2^64 - 1, not '{}'", t));
    if (t.size() > 20 || (t.size() == 20 && t > "18446744073709551615"))
        throw InputError(where, fmt::format("the seed {} is above 2^64 - 1", t));
    return std::stoull(std::string(t));
}

std::vector<std::string> EnsembleSpec::input_names() const {
    std::vector<std::string> out;
    for (const auto& a : grid) out.push_back(a.name);
    for (const auto& v : vary) out.push_back(v.name);
    return out;
}

std::size_t EnsembleSpec::members() const {
    if (!vary.empty()) return samples;
    std::size_t n = grid.empty() ? 0 : 1;
    for (const auto& a : grid) {
        if (n > max_members / a.count)
            throw InputError(a.where, fmt::format("the grid has more than {} points", max_members));
        n *= a.count;
    }
    return n;
}

std::vector<double> EnsembleSpec::inputs(std::size_t index) const {
    std::vector<double> out(grid.size() + vary.size());
    std::size_t rest = index;
    for (std::size_t k = grid.size(); k-- > 0;) {  // the last axis varies fastest
        out[k] = grid[k].value(rest % grid[k].count);
        rest /= grid[k].count;
    }
    if (vary.empty()) return out;
    std::mt19937_64 rng(member_seed(seed, index));
    for (std::size_t k = 0; k < vary.size(); ++k) {
        const Variation& v = vary[k];
        double& x = out[grid.size() + k];
        switch (v.kind) {
            case Distribution::normal: x = v.a + v.b * standard_normal(rng); break;
            case Distribution::uniform: x = v.a + (v.b - v.a) * uniform01(rng); break;
            case Distribution::lognormal: x = std::exp(v.a + v.b * standard_normal(rng)); break;
        }
    }
    return out;
}

std::uint64_t member_seed(std::uint64_t seed, std::size_t index) { return mix(mix(seed) ^ static_cast<std::uint64_t>(index)); }

void check_names(const EnsembleSpec& spec, const std::vector<std::string>& parameters,
                 const std::vector<std::string>& states, const std::vector<std::pair<std::string, double>>& fixed) {
    if (!spec.grid.empty() && !spec.vary.empty())
        throw InputError(spec.vary.front().where, "a sweep takes --grid and an ensemble --vary, not both");
    std::vector<std::string> known = parameters;
    known.insert(known.end(), states.begin(), states.end());
    const auto join = [](const std::vector<std::string>& names) {
        return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
    };
    std::vector<std::string> seen;
    const auto check = [&](const std::string& name, const SourcePos& where) {
        bool found = false;
        for (const auto& k : known) found = found || k == name;
        if (!found) {
            const std::string near = nearest_name(name, known);
            throw InputError(where, fmt::format("'{}' is neither a parameter nor a state variable{} (parameters: {}; "
                                                "initial values: {})",
                                                name, near.empty() ? "" : "; did you mean '" + near + "'?",
                                                join(parameters), join(states)));
        }
        for (const auto& s : seen)
            if (s == name) throw InputError(where, fmt::format("'{}' is varied twice", name));
        for (const auto& [f, value] : fixed)
            if (f == name) throw InputError(where, fmt::format("'{}' is also fixed by --set {}={}", name, f, value));
        seen.push_back(name);
    };
    for (const auto& a : spec.grid) check(a.name, a.where);
    for (const auto& v : spec.vary) check(v.name, v.where);
}

}  // namespace eomc::host
