// Parses the scene's expressions against one symbol table.
//
// A hand-written recursive-descent parser (expression_parser.cpp): it reports every error at
// its file:line:column, binds every name to the scene's own symbol (GiNaC's parser binds I,
// Euler and Catalan to its constants first, and crashes on "sin()"), and bounds what a hostile
// scene can ask for: the nesting depth, the length of an expression and of a number, numbers
// outside double's range, and powers of numbers whose exact value would be huge. Decimal
// literals become exact rationals (0.5 -> 1/2), so that the algebra stays exact and the
// generated code prints the same constants on every machine.
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

// The bounds on one expression (each refused with its place).
inline constexpr int max_expression_depth = 64;              // nested parentheses, calls, signs, exponents
inline constexpr std::size_t max_expression_length = 65536;  // characters
inline constexpr std::size_t max_literal_length = 200;       // characters of one number
inline constexpr std::size_t max_power_bits = 4096;          // the exact value of a power of numbers

class SymbolTable {
public:
    // The one factory: declaring a name twice returns the same symbol. Plain GiNaC::symbol,
    // not realsymbol: realsymbol's type_info lives in each program that uses it, and GiNaC
    // seeds its hash values (and so its term order) with that address — generated code
    // would then change whenever eomc itself is rebuilt.
    GiNaC::symbol declare(const std::string& name, SymbolKind kind);
    bool contains(const std::string& name) const { return kinds_.count(name) != 0; }
    const GiNaC::symbol& symbol(const std::string& name) const;  // a declared name

    // Parses `expr`; only names of the `allowed` kinds may appear (`what` names the place
    // in messages, e.g. "a body position"). Throws InputError at the offending character.
    GiNaC::ex parse(const scene::Expr& expr, unsigned allowed, const std::string& what) const;

private:
    std::map<std::string, GiNaC::symbol> symbols_;
    std::map<std::string, SymbolKind> kinds_;
};

}  // namespace eomc::model
