// libFuzzer target: any bytes as one expression of a scene with a time, parameters, a
// coordinate and its rates. Only InputError may come out of the parser.
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/expression_parser.hpp"
#include "support/diagnostic.hpp"

namespace {

eomc::model::SymbolTable make_table() {
    using eomc::model::SymbolKind;
    eomc::model::SymbolTable table;
    table.declare("t", SymbolKind::time);
    for (const char* p : {"m", "k", "g", "l", "I", "Euler", "Omega"}) table.declare(p, SymbolKind::parameter);
    table.declare("q", SymbolKind::coordinate);
    table.declare("q_dot", SymbolKind::velocity);
    table.declare("q_ddot", SymbolKind::acceleration);
    return table;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const eomc::model::SymbolTable table = make_table();
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        table.parse({text, {"fuzz.toml", 1, 1}}, eomc::model::any_symbol, "the expression");
    } catch (const eomc::InputError&) {
    }
    return 0;
}
