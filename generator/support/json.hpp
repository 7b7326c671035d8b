// The one JSON string writer the command-line outputs share (derive, simulate, equilibria).
#pragma once

#include <string>

#include <fmt/format.h>

namespace eomc {

// s as a JSON string literal, quotes included; control characters escaped.
inline std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += char(c);
        else if (c == '\n') out += "\\n";
        else if (c < 0x20) out += fmt::format("\\u{:04x}", unsigned(c));
        else out += char(c);
    }
    return out + "\"";
}

}  // namespace eomc
