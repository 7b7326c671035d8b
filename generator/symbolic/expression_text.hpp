// One expression as text: GiNaC's own syntax (what JSON carries and the parser reads back) or
// LaTeX; and plain text made safe for LaTeX. Shared by the derivation, inverse-problem and
// equilibria printers.
#pragma once

#include <sstream>
#include <utility>
#include <string>

#include <ginac/ginac.h>

namespace eomc::symbolic {

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

// Plain text (names, prose) with LaTeX's special characters escaped and the mathematical
// characters the prose uses (−, ², √, μ, ∇, the Greek of orbital elements, …) written as
// LaTeX, so that pdflatex's default input encoding takes the result.
inline std::string latex_escape(const std::string& s) {
    static const std::pair<const char*, const char*> unicode[] = {
        {"−", "-"},           {"²", "$^2$"},        {"³", "$^3$"},          {"⁻¹", "$^{-1}$"},   {"√", "$\\surd$"},
        {"∇", "$\\nabla$"},   {"∂", "$\\partial$"}, {"·", "$\\cdot$"},      {"×", "$\\times$"}, {"→", "$\\to$"},
        {"≤", "$\\le$"},      {"≥", "$\\ge$"},      {"≈", "$\\approx$"},    {"°", "$^\\circ$"}, {"μ", "$\\mu$"},
        {"ω", "$\\omega$"},   {"Ω", "$\\Omega$"},   {"ν", "$\\nu$"},        {"η", "$\\eta$"},   {"Φ", "$\\Phi$"},
        {"θ", "$\\theta$"},   {"φ", "$\\varphi$"},  {"λ", "$\\lambda$"},    {"ρ", "$\\rho$"},   {"u̇", "$\\dot u$"},
        {"ẋ", "$\\dot x$"},   {"q̇", "$\\dot q$"},   {"q̈", "$\\ddot q$"},    {"–", "--"},         {"—", "---"},
    };
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        bool replaced = false;
        for (const auto& [from, to] : unicode) {
            const std::size_t n = std::char_traits<char>::length(from);
            if (s.compare(i, n, from) == 0) {
                out += to;
                i += n;
                replaced = true;
                break;
            }
        }
        if (replaced) continue;
        const char c = s[i++];
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

}  // namespace eomc::symbolic
