// Parses the scene's expression strings against one symbol table.
//
// GiNaC's parser reports neither positions nor which name is unknown, so identifiers are
// scanned first to give file:line:column diagnostics; decimal literals are turned into
// exact rationals (0.5 -> 1/2) so that the algebra stays exact and the generated code
// prints the same constants on every machine.
#pragma once

#include <map>
#include <string>

#include <ginac/ginac.h>

#include "scene/scene.hpp"

namespace eomc::model {

// What a name stands for; an expression may be restricted to some kinds.
enum class SymbolKind : unsigned {
    time = 1u << 0,
    parameter = 1u << 1,
    coordinate = 1u << 2,
    velocity = 1u << 3,
    acceleration = 1u << 4,
};
constexpr unsigned operator|(SymbolKind a, SymbolKind b) { return unsigned(a) | unsigned(b); }
constexpr unsigned operator|(unsigned a, SymbolKind b) { return a | unsigned(b); }
inline constexpr unsigned any_symbol = 0x1f;

const char* describe(SymbolKind kind);  // "a coordinate", "a velocity", ...

class SymbolTable {
public:
    // The one factory: declaring a name twice returns the same symbol. Plain GiNaC::symbol,
    // not realsymbol: realsymbol's type_info lives in each program that uses it, and GiNaC
    // seeds its hash values (and so its term order) with that address — generated code
    // would then change whenever eomc itself is rebuilt.
    GiNaC::symbol declare(const std::string& name, SymbolKind kind);
    bool contains(const std::string& name) const { return kinds_.count(name) != 0; }

    // Parses `expr`; only names of the `allowed` kinds may appear (`what` names the place
    // in messages, e.g. "a body position"). Throws InputError at the offending character.
    GiNaC::ex parse(const scene::Expr& expr, unsigned allowed, const std::string& what) const;

private:
    GiNaC::symtab table_;
    std::map<std::string, SymbolKind> kinds_;
};

// "0.25*x + 1e-3" -> "(1/4)*x + (1/1000)"; identifiers (m1, x_dot) are left alone.
std::string exact_decimals(const std::string& text);

}  // namespace eomc::model
