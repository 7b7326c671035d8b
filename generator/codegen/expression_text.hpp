// One expression as text: GiNaC's own syntax (what JSON carries and the parser reads back) or
// LaTeX; and plain text made safe for LaTeX. Shared by the derivation, inverse-problem and
// equilibria printers.
#pragma once

#include <sstream>
#include <string>

#include <ginac/ginac.h>

namespace eomc::codegen {

inline std::string text(const GiNaC::ex& e) {
    std::ostringstream os;
    os << GiNaC::dflt << e;
    return os.str();
}

inline std::string latex(const GiNaC::ex& e) {
    std::ostringstream os;
    os << GiNaC::latex << e;
    return os.str();
}

// Plain text (names, prose) with LaTeX's special characters escaped.
inline std::string latex_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '_': case '#': case '%': case '&': case '$': case '{': case '}': out += '\\'; out += c; break;
            case '\\': out += R"(\textbackslash{})"; break;
            case '^': out += R"(\^{})"; break;
            case '~': out += R"(\~{})"; break;
            default: out += c;
        }
    }
    return out;
}

}  // namespace eomc::codegen
