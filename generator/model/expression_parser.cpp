#include "model/expression_parser.hpp"

#include <cctype>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "model/functions.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

namespace {

// The functions a scene may call (model/functions.hpp), and sqrt.
const std::set<std::string>& known_functions() {
    static const std::set<std::string> names = [] {
        std::set<std::string> out(elementary_functions.begin(), elementary_functions.end());
        out.insert("sqrt");
        return out;
    }();
    return names;
}

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// Length of the numeric literal starting at i (0 if none): 12, 1.5, .5, 2e-3, 1.e4.
std::size_t number_length(const std::string& s, std::size_t i) {
    std::size_t j = i;
    while (j < s.size() && digit(s[j])) ++j;
    if (j < s.size() && s[j] == '.') {
        ++j;
        while (j < s.size() && digit(s[j])) ++j;
    }
    if (j == i || (j == i + 1 && s[i] == '.')) return 0;
    if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        std::size_t k = j + 1;
        if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
        if (k < s.size() && digit(s[k])) {
            while (k < s.size() && digit(s[k])) ++k;
            j = k;
        }
    }
    return j - i;
}

std::string decimal_to_rational(const std::string& lit) {
    std::string mantissa = lit;
    long exponent = 0;
    if (auto e = lit.find_first_of("eE"); e != std::string::npos) {
        mantissa = lit.substr(0, e);
        exponent = std::stol(lit.substr(e + 1));
    }
    std::string digits;
    for (char c : mantissa) {
        if (c == '.') continue;
        digits += c;
    }
    if (auto dot = mantissa.find('.'); dot != std::string::npos) exponent -= long(mantissa.size() - dot - 1);
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size() - 1));
    if (exponent >= 0) return "(" + digits + std::string(std::size_t(exponent), '0') + ")";
    return "(" + digits + "/1" + std::string(std::size_t(-exponent), '0') + ")";
}

struct Identifier {
    std::string name;
    std::size_t offset;
    bool called;  // followed by '('
};

std::vector<Identifier> identifiers(const std::string& s) {
    std::vector<Identifier> out;
    for (std::size_t i = 0; i < s.size();) {
        if (std::size_t n = number_length(s, i); n > 0 && (i == 0 || !ident_char(s[i - 1]))) {
            i += n;
        } else if (ident_start(s[i])) {
            std::size_t j = i;
            while (j < s.size() && ident_char(s[j])) ++j;
            std::size_t k = j;
            while (k < s.size() && std::isspace(static_cast<unsigned char>(s[k]))) ++k;
            out.push_back({s.substr(i, j - i), i, k < s.size() && s[k] == '('});
            i = j;
        } else {
            ++i;
        }
    }
    return out;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

const char* describe(SymbolKind kind) {
    switch (kind) {
        case SymbolKind::time: return "the time";
        case SymbolKind::parameter: return "a parameter";
        case SymbolKind::coordinate: return "a coordinate";
        case SymbolKind::velocity: return "a velocity";
        case SymbolKind::acceleration: return "an acceleration";
    }
    return "a symbol";
}

std::string exact_decimals(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t n = (i == 0 || !ident_char(s[i - 1])) ? number_length(s, i) : 0;
        if (n > 0) {
            out += decimal_to_rational(s.substr(i, n));
            i += n;
        } else if (ident_start(s[i])) {
            while (i < s.size() && ident_char(s[i])) out += s[i++];
        } else {
            out += s[i++];
        }
    }
    return out;
}

namespace {

// LaTeX for a scene name: Greek letters by name, the first underscore a subscript (later
// ones literal), and the _dot/_ddot of velocities as accents.
std::string tex_name(const std::string& name, SymbolKind kind) {
    static const std::set<std::string> greek{
        "alpha", "beta",  "gamma", "delta", "epsilon", "zeta",  "eta",   "theta", "iota",  "kappa",
        "lambda", "mu",   "nu",    "xi",    "pi",      "rho",   "sigma", "tau",   "upsilon", "phi",
        "chi",   "psi",   "omega", "Gamma", "Delta",   "Theta", "Lambda", "Xi",   "Pi",    "Sigma",
        "Upsilon", "Phi", "Psi",   "Omega", "varphi",  "vartheta", "varepsilon"};
    std::string base = name;
    if (kind == SymbolKind::velocity) base = name.substr(0, name.size() - 4);
    if (kind == SymbolKind::acceleration) base = name.substr(0, name.size() - 5);
    std::string head = base, tail;
    if (auto u = base.find('_'); u != std::string::npos) head = base.substr(0, u), tail = base.substr(u + 1);
    std::string tex = greek.count(head) ? "\\" + head + " " : head;
    if (head.size() > 1 && !greek.count(head)) tex = "\\mathit{" + head + "}";
    if (!tail.empty()) {
        std::string sub;
        for (char c : tail) sub += c == '_' ? std::string("\\_") : std::string(1, c);
        tex += "_{" + (greek.count(tail) ? "\\" + tail : sub) + "}";
    }
    if (kind == SymbolKind::velocity) return "\\dot{" + tex + "}";
    if (kind == SymbolKind::acceleration) return "\\ddot{" + tex + "}";
    return tex;
}

}  // namespace

GiNaC::symbol SymbolTable::declare(const std::string& name, SymbolKind kind) {
    if (auto it = table_.find(name); it != table_.end()) return GiNaC::ex_to<GiNaC::symbol>(it->second);
    GiNaC::symbol s(name, tex_name(name, kind));
    table_[name] = s;
    kinds_[name] = kind;
    return s;
}

GiNaC::ex SymbolTable::parse(const scene::Expr& expr, unsigned allowed, const std::string& what) const {
    const std::string& text = expr.text;
    if (text.find_first_not_of(" \t") == std::string::npos)
        throw InputError(expr.pos, fmt::format("empty expression for {}", what));

    for (const Identifier& id : identifiers(text)) {
        const SourcePos at = expr.pos.shifted(int(id.offset));
        if (id.called) {
            if (known_functions().count(id.name)) continue;
            std::vector<std::string> fns(known_functions().begin(), known_functions().end());
            const std::string near = nearest_name(id.name, fns);
            throw InputError(at, fmt::format("unknown function '{}' in {}{}", id.name, what,
                                             near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (id.name == "Pi") continue;
        auto it = kinds_.find(id.name);
        if (it == kinds_.end()) {
            for (const char* suffix : {"_ddot", "_dot"}) {
                if (ends_with(id.name, suffix)) {
                    const std::string base = id.name.substr(0, id.name.size() - std::string(suffix).size());
                    if (!kinds_.count(base) || kinds_.at(base) != SymbolKind::coordinate)
                        throw InputError(at, fmt::format("unknown symbol '{}' in {}: '{}' is not a declared coordinate",
                                                         id.name, what, base));
                }
            }
            std::vector<std::string> names;
            for (const auto& [n, k] : kinds_) names.push_back(n);
            const std::string near = nearest_name(id.name, names);
            throw InputError(at, fmt::format("unknown symbol '{}' in {}{}", id.name, what,
                                             near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (!(unsigned(it->second) & allowed))
            throw InputError(at, fmt::format("'{}' is {}, which may not appear in {}", id.name,
                                             describe(it->second), what));
    }

    GiNaC::symtab table = table_;
    table["Pi"] = GiNaC::Pi;
    GiNaC::parser reader(table, /*strict=*/true);
    try {
        return reader(exact_decimals(text));
    } catch (const std::exception& e) {
        throw InputError(expr.pos, fmt::format("cannot parse {} '{}': {}", what, text, e.what()));
    }
}

}  // namespace eomc::model
