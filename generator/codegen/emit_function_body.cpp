// The text every emitted function is made of: the scene's names as C++ names, one function's body
// over its inputs, blocks, lists and the banner's operation rows (kernel_parts.hpp).
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "codegen/cpp_text.hpp"
#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

using GiNaC::ex;

namespace {

const std::set<std::string>& reserved_words() {
    static const std::set<std::string> words{
        // what the emitted functions call their arguments and helpers
        "t", "x", "p", "out", "out_M", "out_f", "out_G", "out_W", "out_r", "out_phi", "dxdt", "acc", "rate", "S", "std", "Eigen", "Parameters", "eomc",
        // math functions reached through `using std::…`
        "sin", "cos", "tan", "exp", "log", "sqrt", "asin", "acos", "atan", "sinh", "cosh", "tanh", "pow", "abs",
        // C++ keywords a scene name could plausibly be
        "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case", "catch",
        "char", "class", "compl", "concept", "const", "consteval", "constexpr", "constinit", "const_cast",
        "continue", "co_await", "co_return", "co_yield", "decltype", "default", "delete", "do", "double",
        "dynamic_cast", "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto",
        "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq", "nullptr",
        "operator", "or", "or_eq", "private", "protected", "public", "register", "reinterpret_cast", "requires",
        "return", "short", "signed", "sizeof", "static", "static_assert", "static_cast", "struct", "switch",
        "template", "this", "thread_local", "throw", "true", "try", "typedef", "typeid", "typename", "union",
        "unsigned", "using", "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq"};
    return words;
}

}  // namespace

void collect_symbols(const ex& e, std::set<ex, GiNaC::ex_is_less>& out) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        out.insert(e);
        return;
    }
    for (std::size_t i = 0; i < e.nops(); ++i) collect_symbols(e.op(i), out);
}

void LocalNames::add(const NamedSymbol& s) {
    std::string name = s.name;
    checked_identifier(name, "the name");
    while (used_.count(name) || reserved_words().count(name) || is_kernel_macro(name)) name += "_";
    used_.insert(name);
    names_.emplace(s.symbol, name);
}

std::string indent(const std::string& text, int spaces) {
    std::string out, pad(std::size_t(spaces), ' ');
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out += (line.empty() ? "" : pad + line) + "\n";
    if (!out.empty()) out.pop_back();
    return out;
}

std::string function_body(const KernelIR& ir, const LocalNames& names, const Block& block,
                          const std::vector<std::string>& targets, Inputs inputs) {
    std::set<ex, GiNaC::ex_is_less> used;
    for (const auto& t : block.temporaries) collect_symbols(t.value, used);
    for (const auto& o : block.outputs) collect_symbols(o, used);

    std::map<ex, std::string, GiNaC::ex_is_less> printed_names;
    printed_names.emplace(ir.t, "t");
    std::string bindings;
    bool uses_x = false, uses_p = false, uses_acc = false;
    for (std::size_t i = 0; i < ir.state.size(); ++i) {
        if (!used.count(ir.state[i].symbol)) continue;
        if (!inputs.state_array) throw std::runtime_error("a state variable appears where the state is not an input");
        bindings += fmt::format("const S {} = x[{}];\n", names[ir.state[i].symbol], i);
        printed_names.emplace(ir.state[i].symbol, names[ir.state[i].symbol]);
        uses_x = true;
    }
    for (std::size_t i = 0; i < ir.accelerations.size(); ++i) {
        if (!used.count(ir.accelerations[i].symbol)) continue;
        if (!inputs.acceleration_array) throw std::runtime_error("an acceleration appears where none is an input");
        bindings += fmt::format("const S {} = acc[{}];\n", names[ir.accelerations[i].symbol], i);
        printed_names.emplace(ir.accelerations[i].symbol, names[ir.accelerations[i].symbol]);
        uses_acc = true;
    }
    for (const auto& prm : ir.parameters) {
        if (!used.count(prm.symbol)) continue;
        bindings += fmt::format("const S {0} = S(p.{0});\n", names[prm.symbol]);
        printed_names.emplace(prm.symbol, names[prm.symbol]);
        uses_p = true;
    }
    for (const auto& t : block.temporaries)
        printed_names.emplace(t.symbol, GiNaC::ex_to<GiNaC::symbol>(t.symbol).get_name());

    CppExpressionPrinter printer(printed_names);
    std::string code;
    for (const auto& t : block.temporaries)
        code += fmt::format("const S {} = {};\n", GiNaC::ex_to<GiNaC::symbol>(t.symbol).get_name(), printer.print(t.value));
    for (std::size_t k = 0; k < block.outputs.size(); ++k) code += fmt::format("{} = {};\n", targets[k], printer.print(block.outputs[k]));

    std::string head;
    if (!inputs.time_argument && used.count(ir.t)) throw std::runtime_error("the time appears where it is not an input");
    if (inputs.time_argument && !used.count(ir.t)) head += "(void)t;\n";
    if (inputs.state_array && !uses_x) head += "(void)x;\n";
    if (inputs.acceleration_array && !uses_acc) head += "(void)acc;\n";
    if (!uses_p) head += "(void)p;\n";
    for (const auto& f : printer.functions_used()) head += fmt::format("using std::{};\n", f);
    return head + bindings + code;
}

std::vector<std::string> indexed(const std::string& array, std::size_t count, std::size_t offset) {
    std::vector<std::string> out;
    for (std::size_t k = 0; k < count; ++k) out.push_back(fmt::format("{}[{}]", array, k + offset));
    return out;
}

std::vector<std::string> indexed_arrays(std::initializer_list<std::pair<const char*, std::size_t>> arrays) {
    std::vector<std::string> out;
    for (const auto& [array, count] : arrays)
        for (const auto& s : indexed(array, count)) out.push_back(s);
    return out;
}

std::string block_body(const KernelIR& ir, const LocalNames& names, const Block& block, const std::string& array,
                       Inputs inputs) {
    return (block.outputs.empty() ? "(void)" + array + ";\n" : std::string()) +
           function_body(ir, names, block, indexed(array, block.outputs.size()), inputs);
}

std::string quoted_list(const std::vector<std::string>& items, std::string_view what) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", \"" : "\"") + checked_identifier(items[i], what) + "\"";
    return out;
}

std::string literal_list(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + string_literal(items[i]);
    return out;
}

std::string number_list(const std::vector<double>& values, std::string_view what) {
    std::string out;
    for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + double_literal(values[i], what);
    return out;
}

std::string table_row(const char* name, const Block& b) {
    return fmt::format("//   {:<26} {:>8} -> {:>7} ({} temporaries)\n", name, b.ops_before, b.ops_after, b.temporaries.size());
}

std::string comment(const std::string& text, std::size_t width) {
    std::string out, line;
    std::istringstream words(text);
    for (std::string word; words >> word;) {
        word = comment_text(word);
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            out += "// " + line + "\n";
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) out += "// " + line;
    return out;
}

}  // namespace eomc::codegen
