#include "codegen/cpp_text.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "codegen/kernel_macros.hpp"

namespace eomc::codegen {

namespace {

// Length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlongs, no surrogates,
// nothing above U+10FFFF), or 0.
std::size_t utf8_length(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(i);
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c < 0x80) return 1;
    if (c >= 0xC2 && c <= 0xDF) n = 2;
    else if (c == 0xE0) n = 3, lo = 0xA0;
    else if (c >= 0xE1 && c <= 0xEC) n = 3;
    else if (c == 0xED) n = 3, hi = 0x9F;
    else if (c >= 0xEE && c <= 0xEF) n = 3;
    else if (c == 0xF0) n = 4, lo = 0x90;
    else if (c >= 0xF1 && c <= 0xF3) n = 4;
    else if (c == 0xF4) n = 4, hi = 0x8F;
    else return 0;
    if (i + n > s.size()) return 0;
    if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
    return n;
}

std::string hex_escape(unsigned char c) { return fmt::format("\\x{:02X}", c); }

}  // namespace

std::string comment_text(std::string_view text) {
    std::string out;
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const std::size_t n = utf8_length(text, i);
        if (n == 0 || c < 0x20 || c == 0x7F) {
            out += hex_escape(c);  // a line break, another control character, or no UTF-8
            ++i;
            continue;
        }
        const std::string_view point = text.substr(i, n);
        // C1 controls (U+0080–U+009F) and U+2028/U+2029, which editors may show as line breaks.
        if (point.size() == 2 && c == 0xC2 && static_cast<unsigned char>(point[1]) < 0xA0) {
            for (char b : point) out += hex_escape(static_cast<unsigned char>(b));
        } else if (point == "\u2028" || point == "\u2029") {
            for (char b : point) out += hex_escape(static_cast<unsigned char>(b));
        } else {
            out += point;
        }
        i += n;
    }
    // A backslash before the end of the line (white space between counts) splices the next
    // line into the comment in translation phase 2.
    const std::size_t last = out.find_last_not_of(" \t");
    if (last != std::string::npos && out[last] == '\\') out.replace(last, 1, "\\x5C");
    return out;
}

std::string string_literal(std::string_view text) {
    std::string out = "\"";
    for (char ch : text) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if (c == '"' || c == '\\') out += {'\\', ch};
        else if (c < 0x20 || c >= 0x7F) out += fmt::format("\\{:03o}", c);
        else out += ch;
    }
    return out + "\"";
}

bool is_cpp_identifier(std::string_view s) {
    const auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    if (s.empty() || !alpha(s[0])) return false;
    return std::all_of(s.begin() + 1, s.end(), [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}

bool is_kernel_macro(std::string_view name) {
    return std::binary_search(kernel_macro_names.begin(), kernel_macro_names.end(), name);
}

const std::string& checked_identifier(const std::string& name, std::string_view what) {
    if (!is_cpp_identifier(name))
        throw EmitError(fmt::format("{} '{}' is not an identifier and cannot be emitted", what, comment_text(name)));
    return name;
}

std::string double_literal(double value, std::string_view what) {
    if (!std::isfinite(value)) throw EmitError(fmt::format("{} is {}, which a kernel cannot hold", what, value));
    return fmt::format("{}", value);
}

std::string fill_template(std::string_view text, const std::vector<std::pair<std::string, std::string>>& fields) {
    std::map<std::string_view, std::pair<std::string_view, bool>> values;  // key -> (value, used)
    for (const auto& [key, value] : fields)
        if (!values.emplace(key, std::pair<std::string_view, bool>{value, false}).second)
            throw std::logic_error(fmt::format("kernel template field '{}' given twice", key));
    std::string out;
    out.reserve(text.size());
    std::size_t from = 0;
    for (std::size_t open = text.find("{{"); open != std::string_view::npos; open = text.find("{{", from)) {
        const std::size_t close = text.find("}}", open + 2);
        if (close == std::string_view::npos) throw std::logic_error("kernel template: unclosed '{{'");
        const std::string_view key = text.substr(open + 2, close - open - 2);
        const auto it = values.find(key);
        if (it == values.end()) throw std::logic_error(fmt::format("kernel template: unknown field '{}'", key));
        out.append(text.substr(from, open - from));
        out.append(it->second.first);
        it->second.second = true;
        from = close + 2;
    }
    out.append(text.substr(from));
    for (const auto& [key, value] : values)
        if (!value.second) throw std::logic_error(fmt::format("kernel template: field '{}' is never used", key));
    return out;
}

}  // namespace eomc::codegen
