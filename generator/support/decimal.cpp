#include "support/decimal.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <fmt/format.h>

namespace eomc {

namespace {

std::string_view trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t");
    return first == std::string_view::npos ? std::string_view{} : text.substr(first, last - first + 1);
}

}  // namespace

// One decimal grammar for every number given on the command line: [+|-] digits [. digits]
// [e|E [+|-] digits], the whole text, a finite double. Hex floats, "inf" and "nan" are not
// decimals; subnormal numbers are numbers. std::from_chars (C++17 [charconv.from.chars]) is
// locale-independent and reports out-of-range results, unlike strtod/stod, whose ERANGE also
// rejects subnormals. Throws InputError at `where` with the reason.
double parse_decimal(std::string_view text, const SourcePos& where) {
    const std::string_view t = trimmed(text);
    const auto not_a_number = [&] { return InputError(where, fmt::format("'{}' is not a number", text)); };
    if (t.empty() || t.find_first_not_of("0123456789.eE+-") != std::string_view::npos) throw not_a_number();
    std::string_view digits = t;
    if (digits.front() == '+') {  // from_chars takes no '+'; TOML (and people) write +1.5
        digits.remove_prefix(1);
        if (digits.empty() || digits.front() == '+' || digits.front() == '-') throw not_a_number();
    }
    double v = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, std::chars_format::general);
    if (end != digits.data() + digits.size() || ec == std::errc::invalid_argument) throw not_a_number();
    if (ec == std::errc::result_out_of_range)
        throw InputError(where, fmt::format("'{}' is outside the range of a double ({} in magnitude)", text,
                                            std::abs(std::strtod(std::string(digits).c_str(), nullptr)) > 1
                                                ? "above 1.8e308"
                                                : "below 4.9e-324, the smallest subnormal"));
    if (!std::isfinite(v)) throw not_a_number();
    // A subnormal double is a number, but not one the model's exact arithmetic takes: CLN
    // (under GiNaC) has no subnormal floats and stops with "floating point underflow".
    if (v != 0 && std::abs(v) < std::numeric_limits<double>::min())
        throw InputError(where, fmt::format("'{}' is a subnormal double (below 2.2e-308 in magnitude), which eomc's "
                                            "exact arithmetic cannot hold; use 0 or a normal number",
                                            text));
    return v;
}

}  // namespace eomc
