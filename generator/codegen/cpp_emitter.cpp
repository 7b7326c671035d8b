#include "codegen/cpp_emitter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "codegen/solve_plan.hpp"
#include "codegen/templates.hpp"
#include "model/functions.hpp"
#include "model/kepler_function.hpp"

namespace eomc::codegen {

using GiNaC::ex;
using GiNaC::numeric;

// ---------------------------------------------------------------------------------------
// Expressions

namespace {

bool is_negative_term(const ex& e) {
    if (GiNaC::is_a<numeric>(e)) return GiNaC::ex_to<numeric>(e).is_negative();
    if (GiNaC::is_a<GiNaC::mul>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i)
            if (GiNaC::is_a<numeric>(e.op(i))) return GiNaC::ex_to<numeric>(e.op(i)).is_negative();
    }
    return false;
}

// Integers up to 2^53 print exactly as integer literals of any floating type.
bool small_integer(const numeric& x) { return x.is_integer() && GiNaC::abs(x) <= numeric(1L << 53); }

// A number as GiNaC writes it, for messages: a rational's digits can run to thousands, so
// the text is cut in the middle.
std::string printed_numeric(const numeric& x) {
    std::ostringstream os;
    os << GiNaC::ex(x).evalf();
    std::string text = os.str();
    if (text.size() > 40) text = text.substr(0, 20) + "…" + text.substr(text.size() - 12);
    return text;
}

}  // namespace

std::string CppExpressionPrinter::print(const ex& e) { return print(e, sum); }

std::string CppExpressionPrinter::call(const std::string& function, const std::string& argument) {
    functions_.insert(function);
    return function + "(" + argument + ")";
}

std::string CppExpressionPrinter::print_numeric(const numeric& x) {
    if (!x.is_real()) throw EmitError("cannot emit a complex number");
    if (small_integer(x)) return fmt::format("S({})", x.to_long());
    if (x.is_rational() && small_integer(x.numer()) && small_integer(x.denom()))
        return fmt::format("S({})/S({})", x.numer().to_long(), x.denom().to_long());
    // Anything else (huge or tiny rationals, floats): the nearest double, printed exactly. A
    // constant outside double's normal range would print as inf or lose its digits: refused.
    const double value = GiNaC::ex_to<numeric>(GiNaC::ex(x).evalf()).to_double();
    if (!std::isfinite(value) || std::abs(value) < std::numeric_limits<double>::min())
        throw EmitError(fmt::format("the constant {} is outside the range of double ({:g} to {:g} in magnitude)",
                                    comment_text(printed_numeric(x)), std::numeric_limits<double>::min(),
                                    std::numeric_limits<double>::max()));
    return fmt::format("S({:.17e})", value);
}

std::string CppExpressionPrinter::print(const ex& e, Precedence context) {
    std::string text;
    Precedence own = atom;
    if (auto it = names_.find(e); it != names_.end()) {
        return it->second;
    } else if (GiNaC::is_a<numeric>(e)) {
        const numeric& x = GiNaC::ex_to<numeric>(e);
        text = print_numeric(x);
        own = x.is_integer() ? (x.is_negative() ? unary : atom) : product;
        if (x.is_negative() && own == atom) own = unary;
    } else if (GiNaC::is_a<GiNaC::constant>(e)) {
        if (!e.is_equal(GiNaC::Pi)) throw std::runtime_error("cannot emit a constant other than Pi");
        text = "S(3.141592653589793238462643383279502884L)";
    } else if (GiNaC::is_a<GiNaC::symbol>(e)) {
        throw std::runtime_error("no name for symbol '" + GiNaC::ex_to<GiNaC::symbol>(e).get_name() + "'");
    } else if (GiNaC::is_a<GiNaC::add>(e)) {
        text = print_add(e);
        own = sum;
    } else if (GiNaC::is_a<GiNaC::mul>(e)) {
        text = print_mul(e);
        own = is_negative_term(e) ? unary : product;
    } else if (GiNaC::is_a<GiNaC::power>(e)) {
        if (!GiNaC::is_a<numeric>(e.op(1))) {
            text = "pow(" + print(e.op(0), sum) + ", " + print(e.op(1), sum) + ")";
            functions_.insert("pow");
        } else {
            text = print_power(e.op(0), GiNaC::ex_to<numeric>(e.op(1)));
            own = text.find_first_of("*/") == std::string::npos ? atom : product;
        }
    } else if (GiNaC::is_a<GiNaC::function>(e)) {
        const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
        if (name == model::kepler_E_name && e.nops() == 2) {
            // The runtime's solver; the kernel includes model::kepler_E_header (uses_kepler_solver).
            text = std::string(model::kepler_E_cpp) + "(" + print(e.op(0), sum) + ", " + print(e.op(1), sum) + ")";
        } else {
            if (!model::is_elementary_function(name) || e.nops() != 1)
                throw std::runtime_error("cannot emit the function '" + name + "'");
            text = call(name, print(e.op(0), sum));
        }
    } else {
        throw std::runtime_error(std::string("cannot emit an expression of kind ") +
                                 GiNaC::ex_to<GiNaC::basic>(e).class_name());
    }
    return own < context ? "(" + text + ")" : text;
}

std::string CppExpressionPrinter::print_add(const ex& e) {
    std::string out;
    for (const ex& term : order_.operands(e)) {
        if (out.empty()) {
            out = print(term, sum);
        } else if (is_negative_term(term)) {
            out += " - " + print(-term, product);
        } else {
            out += " + " + print(term, product);
        }
    }
    return out;
}

std::string CppExpressionPrinter::print_mul(const ex& e) {
    numeric coefficient = 1;
    std::vector<std::string> numerator, denominator;
    for (const ex& factor : order_.operands(e)) {
        if (GiNaC::is_a<numeric>(factor)) {
            coefficient *= GiNaC::ex_to<numeric>(factor);
        } else if (GiNaC::is_a<GiNaC::power>(factor) && GiNaC::is_a<numeric>(factor.op(1)) &&
                   GiNaC::ex_to<numeric>(factor.op(1)).is_negative() && !names_.count(factor)) {
            const numeric k = -GiNaC::ex_to<numeric>(factor.op(1));
            denominator.push_back(k.is_equal(1) ? print(factor.op(0), atom) : print(GiNaC::pow(factor.op(0), k), atom));
        } else {
            numerator.push_back(print(factor, product));
        }
    }
    std::string out = coefficient.is_negative() ? "-" : "";
    const numeric magnitude = GiNaC::abs(coefficient);
    std::string lead;
    if (!magnitude.is_equal(1) || numerator.empty()) lead = print_numeric(magnitude);
    if (!lead.empty()) numerator.insert(numerator.begin(), lead);
    for (std::size_t i = 0; i < numerator.size(); ++i) out += (i ? "*" : "") + numerator[i];
    if (!denominator.empty()) {
        std::string den;
        for (std::size_t i = 0; i < denominator.size(); ++i) den += (i ? "*" : "") + denominator[i];
        out += "/" + (denominator.size() > 1 ? "(" + den + ")" : den);
    }
    return out;
}

std::string CppExpressionPrinter::print_power(const ex& base, const numeric& k) {
    // numeric::to_long() is exact only inside long's range; an exponent beyond 2^53 would not
    // even print exactly as a floating literal.
    if (k.is_integer() && !small_integer(k))
        throw EmitError(fmt::format("the exponent {} is too large to emit", comment_text(printed_numeric(k))));
    if (k.is_integer()) {
        const long n = k.to_long();
        const long m = n < 0 ? -n : n;
        if (m <= 8) {
            const std::string b = print(base, atom);
            std::string product_text = b;
            for (long i = 1; i < m; ++i) product_text += "*" + b;
            return n < 0 ? "S(1)/" + (m > 1 ? "(" + product_text + ")" : product_text) : product_text;
        }
        functions_.insert("pow");
        return "pow(" + print(base, sum) + ", " + fmt::format("S({})", n) + ")";
    }
    if (k.is_equal(numeric(1, 2))) return call("sqrt", print(base, sum));
    if (k.is_equal(numeric(-1, 2))) return "S(1)/" + call("sqrt", print(base, sum));
    if (k.is_equal(numeric(3, 2))) return print(base, atom) + "*" + call("sqrt", print(base, sum));
    if (k.is_equal(numeric(-3, 2))) return "S(1)/(" + print(base, atom) + "*" + call("sqrt", print(base, sum)) + ")";
    functions_.insert("pow");
    return "pow(" + print(base, sum) + ", " + print_numeric(k) + ")";
}

// ---------------------------------------------------------------------------------------
// The header

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

// C++ names for the scene's names: the same text unless it would clash.
class LocalNames {
public:
    // Parameters first: their names are the Parameters struct's members, which users set by
    // name. A state or acceleration whose name a parameter already has (Delaunay's H and a drag
    // scale height H) is bound under that name with "_" appended, like a reserved word.
    explicit LocalNames(const KernelIR& ir) {
        for (const auto& s : ir.parameters) add(s);
        for (const auto& s : ir.state) add(s);
        for (const auto& s : ir.accelerations) add(s);
    }
    const std::string& operator[](const ex& symbol) const { return names_.at(symbol); }

private:
    void add(const NamedSymbol& s) {
        std::string name = s.name;
        checked_identifier(name, "the name");
        while (used_.count(name) || reserved_words().count(name) || is_kernel_macro(name)) name += "_";
        used_.insert(name);
        names_.emplace(s.symbol, name);
    }
    std::set<std::string> used_;
    std::map<ex, std::string, GiNaC::ex_is_less> names_;
};

void collect_symbols(const ex& e, std::set<ex, GiNaC::ex_is_less>& out) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        out.insert(e);
        return;
    }
    for (std::size_t i = 0; i < e.nops(); ++i) collect_symbols(e.op(i), out);
}

std::string indent(const std::string& text, int spaces) {
    std::string out, pad(std::size_t(spaces), ' ');
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out += (line.empty() ? "" : pad + line) + "\n";
    if (!out.empty()) out.pop_back();
    return out;
}

// How one function's inputs reach its expressions.
struct Inputs {
    bool acceleration_array = false;  // acc[k] holds q̈ (the Jacobian terms)
    bool state_array = true;          // x[k] holds the state (false: the reference, a function of t alone)
    bool time_argument = true;        // t is an argument (false: the restitutions, functions of p alone)
};

// The body of one function: bindings of the inputs it uses, `using std::…` for the
// functions it calls, the temporaries, then `<target>[k] = …;` for each output.
std::string function_body(const KernelIR& ir, const LocalNames& names, const Block& block,
                          const std::vector<std::string>& targets, Inputs inputs = {}) {
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

std::vector<std::string> indexed(const std::string& array, std::size_t count, std::size_t offset = 0) {
    std::vector<std::string> out;
    for (std::size_t k = 0; k < count; ++k) out.push_back(fmt::format("{}[{}]", array, k + offset));
    return out;
}

// A straight-line function past this many operations is emitted in parts, each with only the
// temporaries its outputs need. g++'s register allocation grows faster than linearly with one
// function's size: the 12-link 3-D chain's Jacobian terms (30k operations, 1394 temporaries) took
// 19 s CPU at -O2 as one function. The parts recompute the temporaries they share; the Jacobian,
// the one place this applies, is called once per implicit step (bench/RESULTS.md).
constexpr std::size_t operations_per_part = 4000;

// The outputs [first, last) of `block` with the temporaries they reach.
Block part_of(const Block& block, std::size_t first, std::size_t last) {
    Block part;
    part.outputs.assign(block.outputs.begin() + std::ptrdiff_t(first), block.outputs.begin() + std::ptrdiff_t(last));
    std::set<ex, GiNaC::ex_is_less> needed;
    for (const ex& o : part.outputs) collect_symbols(o, needed);
    for (auto it = block.temporaries.rbegin(); it != block.temporaries.rend(); ++it) {
        if (!needed.count(it->symbol)) continue;
        collect_symbols(it->value, needed);
        part.temporaries.push_back(*it);
    }
    std::reverse(part.temporaries.begin(), part.temporaries.end());
    return part;
}

// A private function's body, and the parts it calls when it is too large for one (above). The
// parts are `name` + "part<k>_" with the same `parameters`, called with `arguments`; `arrays`
// are the output arrays among the parameters (a part writing none of one voids it).
struct SplitBody {
    std::string body;   // the function's body
    std::string parts;  // the parts' definitions, for the private section ("" when not split)
};

SplitBody split_function(const KernelIR& ir, const LocalNames& names, const Block& block,
                         const std::vector<std::string>& targets, Inputs inputs, const std::string& name,
                         const std::string& parameters, const std::string& arguments,
                         const std::vector<std::string>& arrays) {
    const std::size_t count = (block.ops_after + operations_per_part - 1) / operations_per_part;
    if (count < 2 || block.outputs.size() < 2) return {function_body(ir, names, block, targets, inputs), ""};
    SplitBody split;
    const std::size_t n = block.outputs.size(), parts = std::min(count, n);
    for (std::size_t k = 0; k < parts; ++k) {
        const std::size_t first = k * n / parts, last = (k + 1) * n / parts;
        std::string unused;
        for (const auto& array : arrays)
            if (std::none_of(targets.begin() + std::ptrdiff_t(first), targets.begin() + std::ptrdiff_t(last),
                             [&](const std::string& target) { return target.rfind(array + "[", 0) == 0; }))
                unused += "(void)" + array + ";\n";
        const std::vector<std::string> part_targets(targets.begin() + std::ptrdiff_t(first),
                                                    targets.begin() + std::ptrdiff_t(last));
        split.parts += fmt::format(
            "\n    // Outputs {} to {} of {}.\n"
            "    template <class S>\n"
            "    static void {}part{}_({}) {{\n{}\n    }}\n",
            first, last - 1, name, name, k, parameters,
            indent(unused + function_body(ir, names, part_of(block, first, last), part_targets, inputs), 8));
        split.body += fmt::format("{}part{}_({});\n", name, k, arguments);
    }
    split.body = fmt::format("// {} operations after CSE: in {} parts (operations_per_part).\n", block.ops_after, parts) +
                 split.body;
    split.body.pop_back();
    return split;
}

// Names as string literals: identifiers only, so that nothing needs escaping.
std::string quoted_list(const std::vector<std::string>& items, std::string_view what) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", \"" : "\"") + checked_identifier(items[i], what) + "\"";
    return out;
}

// Labels (Santilli's "S1(x,y)") as escaped string literals.
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

// M u̇ = f solved in the kernel's own straight-line code over S (no Eigen), so a SIMD S works.
bool straight_line_solve(const SolvePlan& plan) {
    using M = SolvePlan::Method;
    return plan.method == M::identity || plan.method == M::diagonal || plan.method == M::block_diagonal ||
           plan.method == M::unrolled_ldlt;
}

bool uses_kepler_solver(const KernelIR& ir) {
    for (const Block* b : {&ir.mass_matrix, &ir.forcing, &ir.rhs_explicit, &ir.jacobian_explicit, &ir.mass_and_forcing,
                           &ir.explicit_rates, &ir.explicit_rates_jacobian, &ir.mass_and_jacobian_terms, &ir.invariants,
                           &ir.outputs, &ir.events, &ir.santilli_residuals, &ir.singular_sets,
                           &ir.mass_forcing_and_constraints, &ir.constraint_residuals, &ir.constraint_jacobian,
                           &ir.restitutions, &ir.contact_gaps, &ir.contact_jacobian, &ir.contact_bias,
                           &ir.contact_time_rates, &ir.mass_forcing_and_programs, &ir.program_residuals}) {
        for (const auto& t : b->temporaries)
            if (model::has_kepler_E(t.value)) return true;
        for (const auto& o : b->outputs)
            if (model::has_kepler_E(o)) return true;
    }
    return false;
}

}  // namespace

// A comment block: each line of `text` behind "// ", words made inert (comment_text).
std::string comment(const std::string& text, std::size_t width = 92) {
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

namespace {

// Each step below writes one part of templates/kernel.hpp.in; emit_header fills the template.

// A function body for a block whose output array may be left unused.
std::string block_body(const KernelIR& ir, const LocalNames& names, const Block& block, const std::string& array,
                       Inputs inputs = {}) {
    return (block.outputs.empty() ? "(void)" + array + ";\n" : std::string()) +
           function_body(ir, names, block, indexed(array, block.outputs.size()), inputs);
}

// One row of the banner's operation table.
// Where the rates given in closed form land: dxdt[i] in rhs, and row i of the Jacobian (n_state
// entries from out[i n_state]).
std::pair<std::vector<std::string>, std::vector<std::string>> explicit_rate_targets(const KernelIR& ir) {
    const std::size_t N = ir.state.size();
    std::vector<std::string> rates, rate_rows;
    for (std::size_t i : ir.explicit_index) {
        rates.push_back(fmt::format("dxdt[{}]", i));
        for (std::size_t j = 0; j < N; ++j) rate_rows.push_back(fmt::format("out[{}]", i * N + j));
    }
    return {rates, rate_rows};
}

std::string table_row(const char* name, const Block& b) {
    return fmt::format("//   {:<26} {:>8} -> {:>7} ({} temporaries)\n", name, b.ops_before, b.ops_after, b.temporaries.size());
}

// The members of the Parameters aggregate, with the scene's defaults; PT is double but for a
// batched ensemble's (one value per lane).
std::string parameter_members(const KernelIR& ir, const LocalNames& names) {
    std::string members;
    for (std::size_t i = 0; i < ir.parameters.size(); ++i)
        members += fmt::format("        PT {} = {};\n", names[ir.parameters[i].symbol],
                               double_literal(ir.parameter_defaults[i], "the default of parameter " + ir.parameters[i].name));
    if (!members.empty()) members.pop_back();
    return members;
}

// rhs() and jacobian(): in closed form, or through M u̇ = f solved at run time, with the private
// helpers that path needs.
struct Rates {
    std::string rhs, jacobian, private_part, includes, table;
};

// Whether a kernel's constraint rows are solved in straight-line code (codegen/solve_plan.hpp,
// plan_saddle_point) rather than by the runtime's Schur complement on Eigen.
bool straight_line_constraints(const KernelIR& ir) {
    return !ir.constraint_names.empty() && ir.constraint_plan.method != SolvePlan::Method::eigen_llt &&
           ir.constraint_plan.method != SolvePlan::Method::none;
}

// The straight-line path of emit_constrained_rates: u̇, λ and Wᵀλ from the saddle-point solve
// (codegen/solve_plan.hpp), and the projection's corrections, with no Eigen.
std::string straight_line_constraint_functions(const KernelIR& ir, const LocalNames& names) {
    const std::size_t nu = ir.n_velocities, m = ir.constraint_names.size();
    std::vector<std::string> targets = indexed("udot", nu);
    for (const auto& s : indexed("lambda", m)) targets.push_back(s);
    for (const auto& s : indexed("reaction", nu)) targets.push_back(s);
    std::string out = fmt::format(
        "    // u̇, λ and Wᵀλ of M u̇ − Wᵀλ = f, W u̇ = r: LDLᵀ of [[M, Wᵀ], [W, 0]] in straight-line code, the\n"
        "    // velocities before the multipliers (the Schur complement: M's pivots, then −W M⁻¹ Wᵀ's).\n"
        "    template <class S>\n"
        "    static void constrained_solution_(S t, const S* x, S* udot, S* lambda, S* reaction, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // ẋ from M u̇ − Wᵀλ = f, W u̇ = r; λ and the generalized reactions Wᵀλ too where lambda and\n"
        "    // reaction are not null.\n"
        "    template <class S>\n"
        "    static void constrained_rates_(S t, const S* x, S* dxdt, S* lambda, S* reaction, const Parameters& p) {{\n"
        "        std::array<S, n_velocities> udot, generalized;\n"
        "        std::array<S, n_constraints> multipliers;\n"
        "        constrained_solution_(t, x, udot.data(), multipliers.data(), generalized.data(), p);\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[std::size_t(k)];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_constraints; ++a) lambda[a] = multipliers[std::size_t(a)];\n"
        "        if (reaction)\n"
        "            for (int k = 0; k < n_velocities; ++k) reaction[k] = generalized[std::size_t(k)];\n"
        "    }}\n",
        indent(function_body(ir, names, ir.solved_constraints, targets), 8));
    const auto correction = [&](const char* name, const char* rows, const Block& block) {
        if (block.outputs.empty()) return std::string();
        return fmt::format(
            "\n    // The projection's step C = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ over {},\n"
            "    // n_velocities × {} row-major.\n"
            "    template <class S>\n"
            "    static void {}(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
            rows, block.outputs.size() / nu, name, indent(function_body(ir, names, block, indexed("out", block.outputs.size())), 8));
    };
    out += correction("position_correction_",
                      ir.velocity_correction.outputs.empty() ? "the projected rows (all holonomic: positions and velocities)"
                                                             : "the projected holonomic rows",
                      ir.position_correction);
    out += correction("velocity_correction_", "every projected row", ir.velocity_correction);
    return out;
}

// rhs() and jacobian() of a kernel with constraint rows: u̇ and λ from the Schur complement, in
// straight-line code or by runtime/constraints.hpp; ∂ẋ/∂x by central differences of rhs.
Rates emit_constrained_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t nu = ir.n_velocities, m = ir.constraint_names.size();
    const bool straight = straight_line_constraints(ir);
    Rates r;
    r.includes = straight ? "#include <eomc/runtime/constraint_projection.hpp>\n"
                          : "#include <Eigen/Core>\n#include <Eigen/Cholesky>\n#include <eomc/runtime/constraints.hpp>\n";
    r.rhs = "constrained_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = "// The rates go through the Schur complement: differenced, not derived.\n"
                 "eomc::runtime::central_difference_jacobian(t, x, out, n_state,\n"
                 "                                           [&p](S tau, const S* y, S* dydt) { rhs(tau, y, dydt, p); });";
    std::vector<std::string> targets = indexed("out_M", nu * nu);
    for (const auto& s : indexed("out_f", nu)) targets.push_back(s);
    for (const auto& s : indexed("out_W", m * nu)) targets.push_back(s);
    for (const auto& s : indexed("out_r", m)) targets.push_back(s);
    std::vector<std::string> rates;
    for (std::size_t i : ir.explicit_index) rates.push_back(fmt::format("dxdt[{}]", i));
    std::vector<std::string> residuals = indexed("out", m);
    for (const auto& s : indexed("out_phi", m)) residuals.push_back(s);
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M, f, the constraint rows' W (m × n_velocities, row-major) and r = −bias − stabilisation,\n"
        "    // together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_forcing_and_constraints_(S t, const S* x, S* out_M, S* out_f, S* out_W, S* out_r,\n"
        "                                              const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "{}\n"
        "    // The rows' residuals: f (holonomic) or φ (kinematic) to out, φ to out_phi.\n"
        "    template <class S>\n"
        "    static void constraint_residuals_(S t, const S* x, S* out, S* out_phi, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // W alone, m × n_velocities row-major: what the projection needs.\n"
        "    template <class S>\n"
        "    static void constraint_jacobian_(S t, const S* x, S* out_W, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_forcing_and_constraints, targets), 8),
        indent((rates.empty() ? "(void)dxdt;\n" : std::string()) + function_body(ir, names, ir.explicit_rates, rates), 8),
        straight ? straight_line_constraint_functions(ir, names) : std::string(
        "    // ẋ from M u̇ − Wᵀλ = f, W u̇ = r (runtime/constraints.hpp: the Schur complement on the LDLT of\n"
        "    // M); λ and the generalized reactions Wᵀλ too where lambda and reaction are not null.\n"
        "    template <class S>\n"
        "    static void constrained_rates_(S t, const S* x, S* dxdt, S* lambda, S* reaction, const Parameters& p) {\n"
        "        using Matrix = eomc::runtime::ConstraintMatrix<S>;\n"
        "        using Vector = eomc::runtime::ConstraintVector<S>;\n"
        "        Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n_velocities, n_velocities),\n"
        "            W(n_constraints, n_velocities);\n"
        "        Vector f(n_velocities), r(n_constraints), udot, multipliers;\n"
        "        mass_forcing_and_constraints_(t, x, M.data(), f.data(), W.data(), r.data(), p);\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        eomc::runtime::schur_solve<S>(Matrix(M), f, Matrix(W), r, udot, multipliers);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[k];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_constraints; ++a) lambda[a] = multipliers[a];\n"
        "        if (reaction) {\n"
        "            const Vector generalized = W.transpose() * multipliers;\n"
        "            for (int k = 0; k < n_velocities; ++k) reaction[k] = generalized[k];\n"
        "        }\n"
        "    }\n"),
        indent(function_body(ir, names, ir.constraint_residuals, residuals), 8),
        indent(function_body(ir, names, ir.constraint_jacobian, indexed("out_W", m * nu)), 8));
    r.table = table_row("mass_matrix + forcing + rows", ir.mass_forcing_and_constraints) +
              table_row("explicit rates", ir.explicit_rates) +
              (straight ? table_row("saddle-point solve", ir.solved_constraints) : std::string()) +
              table_row("constraint residuals", ir.constraint_residuals) +
              table_row("constraint jacobian", ir.constraint_jacobian);
    if (straight && !ir.position_correction.outputs.empty())
        r.table += table_row("position correction", ir.position_correction);
    if (straight && !ir.velocity_correction.outputs.empty())
        r.table += table_row("velocity correction", ir.velocity_correction);
    return r;
}

// Whether a kernel's programs are reduced in straight-line code (codegen/solve_plan.hpp,
// reduce_programs) rather than solved on Eigen.
bool straight_line_programs(const KernelIR& ir) { return !ir.reduced_programs.outputs.empty(); }

// The straight-line path of emit_controlled_rates: M's solve and Ā M⁻¹ in generated code, the m × m
// G λ = h by runtime/program/reduced_control.hpp, with no Eigen.
Rates emit_reduced_controlled_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t m = ir.program_names.size();
    Rates r;
    r.includes = "#include <eomc/runtime/constraint_projection.hpp>\n#include <eomc/runtime/program/reduced_control.hpp>\n";
    r.rhs = "controlled_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = "// The rates go through the control solve: differenced, not derived.\n"
                 "eomc::runtime::central_difference_jacobian(t, x, out, n_state,\n"
                 "                                           [&p](S tau, const S* y, S* dydt) { rhs(tau, y, dydt, p); });";
    std::vector<std::string> rates;
    for (std::size_t i : ir.explicit_index) rates.push_back(fmt::format("dxdt[{}]", i));
    r.private_part = fmt::format(
        "\n private:\n"
        "    using ReducedLayout_ = eomc::runtime::program::ReducedLayout<n_velocities, n_programs>;\n\n"
        "    // z = M⁻¹f, Y = M⁻¹D, G = Ā Y, h = c − Ā z and D (row-major, ReducedLayout_): M's solve and\n"
        "    // Ā M⁻¹ in straight-line code; G λ = h is left to a pivoted LU at run time.\n"
        "    template <class S>\n"
        "    static void reduced_programs_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // ẋ from M u̇ = f + D λ, Ā u̇ = c; λ and Q_c = D λ too where lambda and control are not null.\n"
        "    template <class S>\n"
        "    static void controlled_rates_(S t, const S* x, S* dxdt, S* lambda, S* control, const Parameters& p) {{\n"
        "        std::array<S, ReducedLayout_::size> reduced;\n"
        "        std::array<S, n_velocities> udot, generalized;\n"
        "        std::array<S, n_programs> multipliers;\n"
        "        reduced_programs_(t, x, reduced.data(), p);\n"
        "        eomc::runtime::program::reduced_control_solve<n_velocities, n_programs>(reduced.data(), udot.data(),\n"
        "                                                                              multipliers.data(), generalized.data());\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[std::size_t(k)];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_programs; ++a) lambda[a] = multipliers[std::size_t(a)];\n"
        "        if (control)\n"
        "            for (int k = 0; k < n_velocities; ++k) control[k] = generalized[std::size_t(k)];\n"
        "    }}\n\n"
        "    // det(Ā M⁻¹ D): where it vanishes no control in these directions realises the programs.\n"
        "    template <class S>\n"
        "    static S control_determinant_(S t, const S* x, const Parameters& p) {{\n"
        "        std::array<S, ReducedLayout_::size> reduced;\n"
        "        reduced_programs_(t, x, reduced.data(), p);\n"
        "        return eomc::runtime::program::reduced_control_determinant<n_velocities, n_programs>(reduced.data());\n"
        "    }}\n\n"
        "    template <class S>\n"
        "    static void program_residuals_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.reduced_programs, indexed("out", ir.reduced_programs.outputs.size())), 8),
        indent((rates.empty() ? "(void)dxdt;\n" : std::string()) + function_body(ir, names, ir.explicit_rates, rates), 8),
        indent(function_body(ir, names, ir.program_residuals, indexed("out", 2 * m)), 8));
    r.table = table_row("programs, reduced", ir.reduced_programs) +
              table_row("explicit rates", ir.explicit_rates) + table_row("program residuals", ir.program_residuals);
    return r;
}

// rhs() and jacobian() of a kernel with programs (Mei ch. 3): u̇, λ and Q_c = D λ from M u̇ = f + D λ,
// Ā u̇ = c (runtime/program/control.hpp; Udwadia–Kalaba for dependent ideal programs), ∂ẋ/∂x by
// central differences of rhs.
Rates emit_controlled_rates(const KernelIR& ir, const LocalNames& names) {
    if (straight_line_programs(ir)) return emit_reduced_controlled_rates(ir, names);
    const std::size_t nu = ir.n_velocities, m = ir.program_names.size(), k = ir.program_columns.size();
    Rates r;
    r.includes = "#include <Eigen/Core>\n#include <eomc/runtime/constraints.hpp>\n#include <eomc/runtime/program/control.hpp>\n";
    r.rhs = "controlled_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = "// The rates go through the control solve: differenced, not derived.\n"
                 "eomc::runtime::central_difference_jacobian(t, x, out, n_state,\n"
                 "                                           [&p](S tau, const S* y, S* dydt) { rhs(tau, y, dydt, p); });";
    std::vector<std::string> targets = indexed("out_M", nu * nu);
    for (const auto& s : indexed("out_f", nu)) targets.push_back(s);
    for (const auto& s : indexed("out_A", m * nu)) targets.push_back(s);
    for (const auto& s : indexed("out_c", m)) targets.push_back(s);
    for (const auto& s : indexed("out_D", nu * k)) targets.push_back(s);
    std::vector<std::string> rates;
    for (std::size_t i : ir.explicit_index) rates.push_back(fmt::format("dxdt[{}]", i));
    const std::string solve =
        ir.program_redundant ? "eomc::runtime::program::udwadia_kalaba_solve<S>(M, f, A, c, udot, multipliers, generalized);\n"
                             : "eomc::runtime::program::control_solve<S>(M, f, A, D, c, udot, multipliers, generalized);\n";
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M, f, the programs' Ā (m × n_velocities) and c, and the control directions D (n_velocities × k),\n"
        "    // all row-major, together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_forcing_and_programs_(S t, const S* x, S* out_M, S* out_f, S* out_A, S* out_c, S* out_D,\n"
        "                                           const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    template <class S>\n"
        "    struct ControlMatrices_ {{\n"
        "        eomc::runtime::program::Matrix<S> M, A, D;\n"
        "        eomc::runtime::program::Vector<S> f, c;\n"
        "    }};\n\n"
        "    template <class S>\n"
        "    static ControlMatrices_<S> control_matrices_(S t, const S* x, const Parameters& p) {{\n"
        "        using RowMajor = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;\n"
        "        RowMajor M(n_velocities, n_velocities), A(n_programs, n_velocities), D(n_velocities, n_program_controls);\n"
        "        eomc::runtime::program::Vector<S> f(n_velocities), c(n_programs);\n"
        "        mass_forcing_and_programs_(t, x, M.data(), f.data(), A.data(), c.data(), D.data(), p);\n"
        "        return {{M, A, D, f, c}};\n"
        "    }}\n\n"
        "    // ẋ from M u̇ = f + D λ, Ā u̇ = c; λ and Q_c = D λ too where lambda and control are not null.\n"
        "    template <class S>\n"
        "    static void controlled_rates_(S t, const S* x, S* dxdt, S* lambda, S* control, const Parameters& p) {{\n"
        "        const auto [M, A, D, f, c] = control_matrices_(t, x, p);\n"
        "        (void)D;\n"
        "        eomc::runtime::program::Vector<S> udot, multipliers, generalized;\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        {}"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[k];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_program_controls; ++a) lambda[a] = multipliers[a];\n"
        "        if (control)\n"
        "            for (int k = 0; k < n_velocities; ++k) control[k] = generalized[k];\n"
        "    }}\n\n"
        "    // det(Ā M⁻¹ D): where it vanishes no control in these directions realises the programs.\n"
        "    template <class S>\n"
        "    static S control_determinant_(S t, const S* x, const Parameters& p) {{\n"
        "        const auto [M, A, D, f, c] = control_matrices_(t, x, p);\n"
        "        (void)f;\n"
        "        (void)c;\n"
        "        return eomc::runtime::program::control_determinant<S>(M, A, D);\n"
        "    }}\n\n"
        "    template <class S>\n"
        "    static void program_residuals_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_forcing_and_programs, targets), 8),
        indent((rates.empty() ? "(void)dxdt;\n" : std::string()) + function_body(ir, names, ir.explicit_rates, rates), 8),
        solve, indent(function_body(ir, names, ir.program_residuals, indexed("out", 2 * m)), 8));
    r.table = table_row("mass_matrix + forcing + programs", ir.mass_forcing_and_programs) +
              table_row("explicit rates", ir.explicit_rates) + table_row("program residuals", ir.program_residuals);
    return r;
}

// rhs() and jacobian() with M u̇ = f solved in straight-line code (codegen/solve_plan.hpp): M, f
// and the solve in one function, with no Eigen and no arrays for M.
Rates emit_straight_line_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;
    Rates r;
    r.rhs = "explicit_rates_(t, x, dxdt, p);\n"
            "velocity_rates_(t, x, dxdt + velocity_offset, p);";
    r.jacobian = "std::array<S, n_velocities> acc;\n"
                 "velocity_rates_(t, x, acc.data(), p);\n"
                 "explicit_rates_jacobian_(t, x, out, p);\n"
                 "// d(M⁻¹f)/dx = M⁻¹ (∂f/∂x − (∂M/∂x) u̇): the velocity block's rows\n"
                 "velocity_jacobian_(t, x, acc.data(), out + velocity_offset * n_state, p);";
    r.table = table_row("mass_matrix + forcing", ir.mass_and_forcing) + table_row("explicit rates", ir.explicit_rates) +
              table_row("M u̇ = f solved", ir.solved_rates) +
              table_row("mass_matrix + jacobian terms", ir.mass_and_jacobian_terms) +
              table_row("M⁻¹ (jacobian terms)", ir.solved_jacobian_terms) +
              table_row("explicit rates jacobian", ir.explicit_rates_jacobian);
    const auto [rates, rate_rows] = explicit_rate_targets(ir);
    const SplitBody velocity_jacobian =
        split_function(ir, names, ir.solved_jacobian_terms, indexed("out", nu * N), {true}, "velocity_jacobian_",
                       "S t, const S* x, const S* acc, S* out, const Parameters& p", "t, x, acc, out, p", {"out"});
    r.private_part = fmt::format(
        "\n private:\n"
        "    // u̇ = M⁻¹f to out[0 .. n_velocities): M and f together (they share most of their\n"
        "    // subexpressions), then the solve the banner names.\n"
        "    template <class S>\n"
        "    static void velocity_rates_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // M⁻¹G, G = ∂f/∂x − (∂M/∂x) u̇ with u̇ = acc, row-major n_velocities × n_state.\n"
        "    template <class S>\n"
        "    static void velocity_jacobian_(S t, const S* x, const S* acc, S* out, const Parameters& p) {{\n{}\n    }}\n{}\n"
        "    // The rows of ∂ẋ/∂x of the closed-form rates.\n"
        "    template <class S>\n"
        "    static void explicit_rates_jacobian_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.solved_rates, indexed("out", nu)), 8),
        indent(function_body(ir, names, ir.explicit_rates, rates), 8),
        indent(velocity_jacobian.body, 8), velocity_jacobian.parts,
        indent(function_body(ir, names, ir.explicit_rates_jacobian, rate_rows), 8));
    return r;
}

Rates emit_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;
    Rates r;
    if (!ir.constraint_names.empty()) return emit_constrained_rates(ir, names);
    if (!ir.program_names.empty()) return emit_controlled_rates(ir, names);
    if (ir.explicit_solution) {
        r.rhs = function_body(ir, names, ir.rhs_explicit, indexed("dxdt", N));
        if (ir.has_jacobian) r.jacobian = function_body(ir, names, ir.jacobian_explicit, indexed("out", N * N));
        r.table = table_row("rhs (u̇ in closed form)", ir.rhs_explicit) +
                  (ir.has_jacobian ? table_row("jacobian", ir.jacobian_explicit) : std::string());
        return r;
    }
    if (ir.solve_plan.method != SolvePlan::Method::eigen_llt) return emit_straight_line_rates(ir, names);
    // Past unrolled_limit velocities in one block: Eigen's LLT (M is symmetric positive definite).
    r.includes = "#include <limits>\n#include <Eigen/Core>\n#include <Eigen/Cholesky>\n";  // not Dense: twice the compile time
    // Fixed sizes keep small kernels off the heap; past 4096 entries in G a scalar of 16
    // bytes (float128) would near Eigen's 128 KiB limit on fixed-size objects, which is a
    // static assertion, so large systems use dynamic sizes.
    const bool fixed = nu * N <= 4096;
    const std::string square = fixed ? "Eigen::Matrix<S, n_velocities, n_velocities, Eigen::RowMajor> M;\n"
                                     : "Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n_velocities, n_velocities);\n";
    const std::string column = fixed ? "Eigen::Matrix<S, n_velocities, 1> f;\n"
                                     : "Eigen::Matrix<S, Eigen::Dynamic, 1> f(n_velocities);\n";
    const std::string vector_type = fixed ? "Eigen::Matrix<S, n_velocities, 1>" : "Eigen::Matrix<S, Eigen::Dynamic, 1>";
    const std::string wide_type = fixed ? "Eigen::Matrix<S, n_velocities, n_state, Eigen::RowMajor>"
                                        : "Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>";
    const std::string wide_size = fixed ? "" : "(n_velocities, n_state)";
    // A failed factorization (M not positive definite: singular where the coordinates fail) gives
    // NaN, which the runtime's checker stops on, never a finite guess.
    const std::string not_definite = "if (llt.info() != Eigen::Success) {\n"
                                     "    for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = std::numeric_limits<S>::quiet_NaN();\n"
                                     "    return;\n"
                                     "}\n";
    r.rhs = square + column +
            "mass_matrix_and_forcing_(t, x, M.data(), f.data(), p);\n"
            "explicit_rates_(t, x, dxdt, p);\n"
            "const auto llt = M.llt();\n" + not_definite +
            "Eigen::Map<" + vector_type + ">(dxdt + velocity_offset" + (fixed ? "" : ", n_velocities") + ") = llt.solve(f);";
    r.jacobian = square + column +
                 "mass_matrix_and_forcing_(t, x, M.data(), f.data(), p);\n"
                 "const auto llt = M.llt();\n"
                 "if (llt.info() != Eigen::Success) {\n"
                 "    for (int k = 0; k < n_state * n_state; ++k) out[k] = std::numeric_limits<S>::quiet_NaN();\n"
                 "    return;\n"
                 "}\n"
                 "const " + vector_type + " acc = llt.solve(f);\n" +
                 wide_type + " G" + wide_size + ";\n"
                 "mass_matrix_and_jacobian_terms_(t, x, acc.data(), M.data(), G.data(), p);\n"
                 "explicit_rates_jacobian_(t, x, out, p);\n"
                 "// d(M⁻¹f)/dx = M⁻¹ (∂f/∂x − (∂M/∂x) u̇)\n"
                 "const " + wide_type + " lower = llt.solve(G);\n"
                 "for (int i = 0; i < n_velocities; ++i)\n"
                 "    for (int j = 0; j < n_state; ++j) out[(velocity_offset + i) * n_state + j] = lower(i, j);";
    r.table = table_row("mass_matrix + forcing", ir.mass_and_forcing) + table_row("explicit rates", ir.explicit_rates);
    if (ir.has_jacobian)
        r.table += table_row("mass_matrix + jacobian terms", ir.mass_and_jacobian_terms) +
                   table_row("explicit rates jacobian", ir.explicit_rates_jacobian);
    std::vector<std::string> mf = indexed("out_M", nu * nu);
    for (const auto& s : indexed("out_f", nu)) mf.push_back(s);
    std::vector<std::string> mg = indexed("out_M", nu * nu);
    for (const auto& s : indexed("out_G", nu * N)) mg.push_back(s);
    const auto [rates, rate_rows] = explicit_rate_targets(ir);
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M and f together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_matrix_and_forcing_(S t, const S* x, S* out_M, S* out_f, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_and_forcing, mf), 8),
        indent(function_body(ir, names, ir.explicit_rates, rates), 8));
    if (!ir.has_jacobian) return r;
    const SplitBody terms = split_function(ir, names, ir.mass_and_jacobian_terms, mg, {true}, "mass_matrix_and_jacobian_terms_",
                                           "S t, const S* x, const S* acc, S* out_M, S* out_G, const Parameters& p",
                                           "t, x, acc, out_M, out_G, p", {"out_M", "out_G"});
    r.private_part += fmt::format(
        "\n    // M and G = ∂f/∂x − (∂M/∂x) u̇, with u̇ = acc, both row-major.\n"
        "    template <class S>\n"
        "    static void mass_matrix_and_jacobian_terms_(S t, const S* x, const S* acc, S* out_M, S* out_G, const Parameters& p) {{\n{}\n    }}\n{}\n"
        "    // The rows of ∂ẋ/∂x of the closed-form rates.\n"
        "    template <class S>\n"
        "    static void explicit_rates_jacobian_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(terms.body, 8), terms.parts, indent(function_body(ir, names, ir.explicit_rates_jacobian, rate_rows), 8));
    return r;
}

// The body of outputs(). They may read u̇: computed once by rhs and handed over as `acc`.
std::string outputs_body(const KernelIR& ir, const LocalNames& names) {
    if (!ir.program_names.empty()) {
        // The residuals (program_<name>), λ (lambda_<column>) and Q_c = D λ (Qc_<coordinate>) after the scene's own.
        std::string body = fmt::format(
            "std::array<S, n_state> rate;\n"
            "std::array<S, 2 * n_programs> program_residual_;\n"
            "std::array<S, n_program_controls> program_lambda_;\n"
            "std::array<S, n_velocities> program_control_;\n"
            "controlled_rates_(t, x, rate.data(), program_lambda_.data(), program_control_.data(), p);\n"
            "program_residuals_(t, x, program_residual_.data(), p);\n"
            "for (int a = 0; a < n_programs; ++a) out[{0} + a] = program_residual_[std::size_t(2 * a)];\n"
            "for (int a = 0; a < n_program_controls; ++a) out[{0} + n_programs + a] = program_lambda_[std::size_t(a)];\n"
            "for (int k = 0; k < n_velocities; ++k) out[{0} + n_programs + n_program_controls + k] = program_control_[std::size_t(k)];\n",
            ir.n_user_outputs);
        if (ir.n_user_outputs == 0) return body;
        return body + "const S* acc = rate.data() + velocity_offset;\n" +
               function_body(ir, names, ir.outputs, indexed("out", ir.n_user_outputs), {true});
    }
    if (!ir.constraint_names.empty()) {
        // λ (lambda_<row>) and the generalized reactions Wᵀλ (reaction_<coordinate>) after the scene's own.
        std::string body = fmt::format(
            "std::array<S, n_state> rate;\n"
            "std::array<S, n_constraints> constraint_lambda_;\n"
            "std::array<S, n_velocities> constraint_reaction_;\n"
            "constrained_rates_(t, x, rate.data(), constraint_lambda_.data(), constraint_reaction_.data(), p);\n"
            "for (int a = 0; a < n_constraints; ++a) out[{0} + a] = constraint_lambda_[std::size_t(a)];\n"
            "for (int k = 0; k < n_velocities; ++k) out[{0} + n_constraints + k] = constraint_reaction_[std::size_t(k)];\n",
            ir.n_user_outputs);
        if (ir.n_user_outputs == 0) return body;
        return body + "const S* acc = rate.data() + velocity_offset;\n" +
               function_body(ir, names, ir.outputs, indexed("out", ir.n_user_outputs), {true});
    }
    if (ir.output_names.empty()) return "(void)t;\n(void)x;\n(void)out;\n(void)p;";
    return "std::array<S, n_state> rate;\nrhs(t, x, rate.data(), p);\nconst S* acc = rate.data() + velocity_offset;\n" +
           function_body(ir, names, ir.outputs, indexed("out", ir.output_names.size()), {true});
}

// acceleration(t, q) of a separable system, for the splitting methods.
std::string acceleration_function(const KernelIR& ir) {
    if (!ir.separable) return "";
    return "\n    // q̈ = a(t, q): the velocities do not enter the forces, so they are left at zero.\n"
           "    template <class S>\n"
           "    static void acceleration(S t, const S* q, S* a, const Parameters& p) {\n"
           "        std::array<S, n_state> x{}, rate;\n"
           "        for (int i = 0; i < n_coordinates; ++i) x[i] = q[i];\n"
           "        rhs(t, x.data(), rate.data(), p);\n"
           "        for (int i = 0; i < n_coordinates; ++i) a[i] = rate[velocity_offset + i];\n"
           "    }\n";
}

// A unit quaternion's rates keep |e| = 1 only to the integrator's error; the runtime's drivers
// call project(t, x) after every accepted step when a kernel has one. The body is
// runtime::renormalise_quaternion (runtime/quaternion.hpp) written out: the bundled
// free_disk_tube_ball kernel prints it so, and tests/runtime_routines checks that the two agree.
std::string unit_renormalisation(const KernelIR& ir) {
    std::string body;
    for (std::size_t k : ir.unit_quaternions) {
        body += fmt::format("        {{\n            const S norm = sqrt(x[{0}] * x[{0}] + x[{1}] * x[{1}] + x[{2}] * x[{2}] + "
                            "x[{3}] * x[{3}]);\n",
                            k, k + 1, k + 2, k + 3);
        body += fmt::format("            for (int i = {}; i < {}; ++i) x[i] /= norm;\n        }}\n", k, k + 4);
    }
    for (std::size_t k : ir.unit_vectors) {
        body += fmt::format("        {{\n            const S norm = sqrt(x[{0}] * x[{0}] + x[{1}] * x[{1}] + x[{2}] * x[{2}]);\n",
                            k, k + 1, k + 2);
        body += fmt::format("            for (int i = {}; i < {}; ++i) x[i] /= norm;\n        }}\n", k, k + 3);
    }
    return body;
}

std::string unit_projection(const KernelIR& ir) {
    if (ir.unit_quaternions.empty() && ir.unit_vectors.empty()) return "";
    const std::string body = "        (void)t;\n        (void)p;\n        using std::sqrt;\n" + unit_renormalisation(ir);
    if (ir.unit_quaternions.empty())
        return "\n    // Puts Poisson's vertical back on |γ| = 1, a Casimir of the equations that integration keeps only\n"
               "    // to its error (the runtime calls it after every accepted step; Hairer, Lubich, Wanner,\n"
               "    // Geometric Numerical Integration, 2nd ed., IV.4, standard projection).\n"
               "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
               body + "    }\n";
    return "\n    // Puts the attitude quaternion back on |e| = 1 (the runtime calls it after every accepted\n"
           "    // step). R(e)/|e|² is orthogonal for any |e|, so this only keeps e well scaled.\n"
           "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
           body + "    }\n";
}

// Encke's rectification: project() calls the runtime's (runtime/orbit/encke.hpp) with the
// reference orbit the state describes, which the kernel writes as a private function.
struct Rectification {
    std::string project, private_part;
};

Rectification rectification(const KernelIR& ir, const LocalNames& names) {
    const RectificationIR& r = *ir.rectification;
    Rectification out;
    out.project = fmt::format(
        "\n    // Encke's rectification (Battin §9.3; runtime/orbit/encke.hpp), which the runtime calls after\n"
        "    // every accepted step: once |δ| > rectification_ratio |ρ| the reference becomes the osculating\n"
        "    // ellipse of the total state at t, and δ is re-expressed in it.\n"
        "    static constexpr double rectification_ratio = {ratio};\n\n"
        "    template <class S>\n"
        "    static void project(S t, S* x, const Parameters& p) {{\n"
        "        const auto reference = [&p](S tau, const S* y, S* out) {{ reference_orbit_(tau, y, out, p); }};\n"
        "        eomc::runtime::encke_rectify(t, x, eomc::runtime::EnckeLayout{{{deviation}, {elements}, {count}}},\n"
        "                                     rectification_ratio, reference);\n"
        "    }}\n",
        fmt::arg("ratio", fmt::format("{}", r.ratio)), fmt::arg("deviation", r.deviation),
        fmt::arg("elements", r.elements), fmt::arg("count", r.count));
    out.private_part = fmt::format(
        "    // The reference orbit at t: ρ, ρ̇ from the reference elements in the state, then μ.\n"
        "    template <class S>\n"
        "    static void reference_orbit_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(block_body(ir, names, r.reference, "out"), 8));
    return out;
}

// ∂ẋ/∂x, only in kernels lowered with it (LowerOptions::jacobian): the rest keep their compile
// time and size.
std::string jacobian_function(const std::string& body) {
    return fmt::format(
        "\n    // ∂ẋ/∂x, row-major n_state×n_state.\n"
        "    template <class S>\n"
        "    static void jacobian(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(body, 8));
}

// The variational equations ride on the kernel's own rhs and symbolic Jacobian
// (runtime/variational.hpp); only on request, so that other kernels keep their bytes.
std::string variational_function(const KernelIR& ir) {
    return fmt::format(
        "\n    // Variational equations (runtime/variational.hpp): y = (x, Φ), Φ row-major n_state × n_state,\n"
        "    // with Φ̇ = (∂ẋ/∂x) Φ through jacobian(). From Φ(t0) = I, δx(t) = Φ(t) δx(t0) to first order.\n"
        "    static constexpr int n_variational = n_state + n_state * n_state;\n\n"
        "    template <class S>\n"
        "    static void variational_rhs(S t, const S* y, S* dydt, const Parameters& p) {{\n"
        "        eomc::runtime::variational_rhs<Basic{}>(t, y, dydt, p);\n"
        "    }}\n",
        checked_identifier(ir.struct_name, "the kernel's name"));
}

// Only kernels with constraint rows carry them, so that no other kernel changes: the rows'
// names, their residuals and the projection after every accepted step (runtime/constraints.hpp),
// which also renormalises a unit quaternion first when the kernel has one.
std::string constraints_part(const KernelIR& ir) {
    if (ir.constraint_names.empty()) return "";
    const std::size_t m = ir.constraint_names.size();
    std::string holonomic, projected;
    bool projects = false;
    for (std::size_t a = 0; a < m; ++a) {
        holonomic += fmt::format("{}{}", a ? ", " : "", ir.constraint_holonomic[a] ? "true" : "false");
        projected += fmt::format("{}{}", a ? ", " : "", ir.constraint_projected[a] ? "true" : "false");
        projects = projects || ir.constraint_projected[a];
    }
    std::string out = fmt::format(
        "\n    // Bilateral constraint rows: M u̇ − Wᵀλ = f, W u̇ = −bias − stabilisation; λ is output as\n"
        "    // lambda_<row>, the generalized reactions Wᵀλ as reaction_<coordinate>.\n"
        "    static constexpr int n_constraints = {};\n"
        "    static constexpr std::array<const char*, n_constraints> constraint_names{{ {} }};\n"
        "    // Holonomic rows f(q, t) = 0; the others are kinematic, φ(q, u, t) = 0.\n"
        "    static constexpr std::array<bool, n_constraints> constraint_holonomic{{ {} }};\n"
        "    // Rows that project() puts back on the manifold after every accepted step.\n"
        "    static constexpr std::array<bool, n_constraints> constraint_projected{{ {} }};\n\n"
        "    // One residual per row: f (holonomic) or φ (kinematic).\n"
        "    template <class S>\n"
        "    static void constraint_residuals(S t, const S* x, S* out, const Parameters& p) {{\n"
        "        std::array<S, n_constraints> phi;\n"
        "        constraint_residuals_(t, x, out, phi.data(), p);\n"
        "    }}\n",
        m, quoted_list(ir.constraint_names, "a constraint name"), holonomic, projected);
    if (!projects && ir.unit_quaternions.empty() && ir.unit_vectors.empty()) return out;
    std::string body;
    if (!ir.unit_quaternions.empty() || !ir.unit_vectors.empty())
        body += "        using std::sqrt;\n" + unit_renormalisation(ir);
    if (projects && straight_line_constraints(ir)) {
        const auto correction = [](const Block& block, const char* name) {
            return block.outputs.empty() ? std::string("[](S, const S*, S*) {}")
                                         : fmt::format("[&p](S tau, const S* y, S* C) {{ {}(tau, y, C, p); }}", name);
        };
        body += fmt::format(
            "        eomc::runtime::project_by_corrections(\n"
            "            t, x, eomc::runtime::ConstraintLayout{{n_coordinates, velocity_offset, n_velocities, n_constraints}},\n"
            "            constraint_projected.data(), constraint_holonomic.data(),\n"
            "            [&p](S tau, const S* y, S* f, S* phi) {{ constraint_residuals_(tau, y, f, phi, p); }},\n"
            "            {},\n"
            "            {});\n",
            correction(ir.position_correction, "position_correction_"),
            ir.velocity_correction.outputs.empty() ? correction(ir.position_correction, "position_correction_")
                                                   : correction(ir.velocity_correction, "velocity_correction_"));
    } else if (projects)
        body +=
            "        eomc::runtime::project_onto_constraints(\n"
            "            t, x, eomc::runtime::ConstraintLayout{n_coordinates, velocity_offset, n_velocities, n_constraints},\n"
            "            constraint_projected.data(), constraint_holonomic.data(),\n"
            "            [&p](S tau, const S* y, S* f, S* phi) { constraint_residuals_(tau, y, f, phi, p); },\n"
            "            [&p](S tau, const S* y, S* W) { constraint_jacobian_(tau, y, W, p); },\n"
            "            [&p](S tau, const S* y, S* M) { mass_matrix(tau, y, M, p); });\n";
    else
        body = "        (void)t;\n        (void)p;\n" + body;
    out += "\n    // After every accepted step (the runtime calls it): the M-metric projection onto the projected\n"
           "    // rows, positions then velocities (Hairer, Lubich, Wanner, Geometric Numerical Integration,\n"
           "    // 2nd ed., IV.4, Algorithm 4.2).\n"
           "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
           body + "    }\n";
    return out;
}

// A kernel with bilateral and unilateral rows hands the contact drivers its bilateral rows too (the
// contact phase, the impacts and the projection keep them active; runtime/contact/event_driven.hpp).
std::string bilateral_rows_for_contacts() {
    return "\n    // The bilateral rows for the contact drivers: the residuals f (holonomic) or φ (kinematic) to out, φ\n"
           "    // to out_phi, W (n_constraints × n_velocities, row-major) to out_W and r of W u̇ = r to out_r.\n"
           "    template <class S>\n"
           "    static void constraint_rows(S t, const S* x, S* out, S* out_phi, S* out_W, S* out_r, const Parameters& p) {\n"
           "        std::array<S, n_velocities * n_velocities> M;\n"
           "        std::array<S, n_velocities> f;\n"
           "        mass_forcing_and_constraints_(t, x, M.data(), f.data(), out_W, out_r, p);\n"
           "        constraint_residuals_(t, x, out, out_phi, p);\n"
           "    }\n";
}

// Only kernels with unilateral rows carry them, so that no other kernel changes: the rows' names,
// which are kinematic, the restitution coefficients, the gaps, W and the bias (runtime/kernel.hpp,
// ContactKernel; the host builds runtime::contact::ContactSystem from them).
std::string contacts_part(const KernelIR& ir, const LocalNames& names) {
    if (ir.contact_names.empty()) return "";
    const std::size_t m = ir.contact_names.size();
    std::string kinematic;
    for (std::size_t a = 0; a < m; ++a) kinematic += fmt::format("{}{}", a ? ", " : "", ir.contact_kinematic[a] ? "true" : "false");
    Inputs parameters_only;
    parameters_only.state_array = false;
    parameters_only.time_argument = false;
    return fmt::format(
        "\n    // Unilateral constraints (Mei, Special Topics in Analytical Mechanics, ch. 6): a gap f(q, t) >= 0\n"
        "    // (an impact when it closes) or a kinematic row phi(q, u, t) >= 0 (§6.7), each with Newton's\n"
        "    // restitution e; on the boundary M u̇ = f + Wᵀλ with λ >= 0, and f̈ (φ̇) = W u̇ + bias.\n"
        "    static constexpr int n_contacts = {};\n"
        "    static constexpr std::array<const char*, n_contacts> contact_names{{ {} }};\n"
        "    // Kinematic (velocity-level) rows: gaps() writes phi for them, and they take no impacts.\n"
        "    static constexpr std::array<bool, n_contacts> contact_kinematic{{ {} }};\n\n"
        "    // Newton's coefficients of restitution, one per row.\n"
        "    template <class S>\n"
        "    static void restitutions(const Parameters& p, S* out) {{\n{}\n    }}\n\n"
        "    // One value per row: f (a gap) or phi (a kinematic row).\n"
        "    template <class S>\n"
        "    static void gaps(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // W, n_contacts × n_velocities row-major: ∂f/∂q (a gap, q̇ = u) or ∂phi/∂u (a kinematic row).\n"
        "    template <class S>\n"
        "    static void contact_jacobian(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // bias = f̈ − W u̇ (a gap) or φ̇ − W u̇ (a kinematic row), one per row.\n"
        "    template <class S>\n"
        "    static void contact_bias(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        m, literal_list(ir.contact_names), kinematic,
        indent(block_body(ir, names, ir.restitutions, "out", parameters_only), 8),
        indent(block_body(ir, names, ir.contact_gaps, "out"), 8),
        indent(block_body(ir, names, ir.contact_jacobian, "out"), 8),
        indent(block_body(ir, names, ir.contact_bias, "out"), 8)) +
           (ir.contact_time_rates.outputs.empty()
                ? std::string()
                : fmt::format("\n    // w = ∂f/∂t, one per row: a moving gap's rate is ḟ = W u + w (0 for a kinematic row).\n"
                              "    template <class S>\n"
                              "    static void contact_time_rates(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
                              indent(block_body(ir, names, ir.contact_time_rates, "out"), 8))) +
           (ir.constraint_names.empty() ? std::string() : bilateral_rows_for_contacts());
}

// Only kernels of scenes with [events] carry them, so that no other kernel changes.
std::string events_part(const KernelIR& ir, const LocalNames& names) {
    if (ir.event_names.empty()) return "";
    std::string directions, terminal;
    for (std::size_t k = 0; k < ir.event_names.size(); ++k) {
        directions += fmt::format("{}{}", k ? ", " : "", ir.event_directions[k]);
        terminal += fmt::format("{}{}", k ? ", " : "", ir.event_terminal[k] ? "true" : "false");
    }
    return fmt::format(
        "\n    // Events (scene [events]): g_i(t, x), whose zero crossings the runtime locates.\n"
        "    static constexpr int n_events = {};\n"
        "    static constexpr std::array<const char*, n_events> event_names{{ {} }};\n"
        "    // +1: upward crossings (g from negative to positive) only, -1: downward only, 0: both.\n"
        "    static constexpr std::array<int, n_events> event_directions{{ {} }};\n"
        "    // A terminal event stops the integration at its time.\n"
        "    static constexpr std::array<bool, n_events> event_terminal{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void events(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        ir.event_names.size(), quoted_list(ir.event_names, "an event name"), directions, terminal,
        indent(block_body(ir, names, ir.events, "out"), 8));
}

// One accessor per invariant, by its name.
std::string invariant_accessors(const KernelIR& ir) {
    std::string accessors;
    for (std::size_t k = 0; k < ir.invariant_names.size(); ++k) {
        accessors += fmt::format(
            "\n    template <class S>\n    static S {}(S t, const S* x, const Parameters& p) {{\n"
            "        std::array<S, n_invariants> all;\n        invariants(t, x, all.data(), p);\n"
            "        return all[{}];\n    }}\n",
            checked_identifier(ir.invariant_names[k], "an invariant name"), k);
    }
    return accessors;
}

// Newtonian scenes only, so that no other kernel changes: the self-adjointness residuals.
std::string santilli_residuals(const KernelIR& ir, const LocalNames& names) {
    if (ir.santilli_residual_names.empty()) return "";
    return fmt::format(
        "\n    // Santilli's conditions S1–S5 of variational self-adjointness of the fundamental form\n"
        "    // A(t,q,q̇) q̈ + B(t,q,q̇) = 0 (D = ∂_t + q̇_k ∂/∂q_k), one residual each; all vanish\n"
        "    // identically iff the equations as given are Euler–Lagrange equations (`eomc inverse`).\n"
        "    static constexpr int n_santilli_residuals = {};\n"
        "    static constexpr std::array<const char*, n_santilli_residuals> santilli_residual_names{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void santilli_residuals(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        ir.santilli_residual_names.size(), literal_list(ir.santilli_residual_names),
        indent(block_body(ir, names, ir.santilli_residuals, "out"), 8));
}

// Only kernels with programs carry them: names, laws and residuals (Mei ch. 3).
std::string programs_part(const KernelIR& ir) {
    if (ir.program_names.empty()) return "";
    return fmt::format(
        "\n    // Programs realised by controls (Mei ch. 3): M u̇ = f + D λ, Ā u̇ = c. Laws: configuration (1) or\n"
        "    // phase (0), then α, β (ω̈ + 2αω̇ + β²ω = 0) and κ (φ̇ + κφ = 0); all 0 for the open loop.\n"
        "    static constexpr int n_programs = {};\n"
        "    static constexpr int n_program_controls = {};\n"
        "    static constexpr std::array<const char*, n_programs> program_names{{ {} }};\n"
        "    static constexpr std::array<double, 4 * n_programs> program_laws{{ {} }};\n\n"
        "    // ω and ω̇ (configuration programs) or φ and 0, two per program.\n"
        "    template <class S>\n"
        "    static void program_residuals(S t, const S* x, S* out, const Parameters& p) {{\n"
        "        program_residuals_(t, x, out, p);\n"
        "    }}\n",
        ir.program_names.size(), ir.program_columns.size(), quoted_list(ir.program_names, "a program name"),
        number_list(ir.program_laws, "a program's gain"));
}

// Only kernels whose mass matrix has a singular set carry it, so that no other kernel changes.
std::string singular_sets_part(const KernelIR& ir, const LocalNames& names) {
    // A kernel with programs watches det(Ā M⁻¹ D) too, as one more indicator (computed at run time).
    const bool control = !ir.program_names.empty() && !ir.program_redundant;
    if (ir.singular_set_names.empty() && !control) return "";
    std::vector<std::string> set_names = ir.singular_set_names;
    std::vector<int> set_orders = ir.singular_set_orders;
    std::string body = ir.singular_set_names.empty() ? std::string() : block_body(ir, names, ir.singular_sets, "out");
    if (control) {
        set_names.push_back("det(A M^-1 D) = 0");
        set_orders.push_back(1);
        body += fmt::format("{}out[{}] = control_determinant_(t, x, p);", body.empty() || body.back() == '\n' ? "" : "\n",
                            ir.singular_set_names.size());
    }
    std::string orders;
    for (std::size_t k = 0; k < set_orders.size(); ++k) orders += fmt::format("{}{}", k ? ", " : "", set_orders[k]);
    return fmt::format(
        "\n    // Where det M = 0 (a coordinate singularity, as the gimbal lock of Euler angles){}: indicators\n"
        "    // s_k(t, x) of the sets s_k = 0, each with its power in det M; a simulation stops before them.\n"
        "    static constexpr int n_singular_sets = {};\n"
        "    static constexpr std::array<const char*, n_singular_sets> singular_set_names{{ {} }};\n"
        "    static constexpr std::array<int, n_singular_sets> singular_set_orders{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void singular_sets(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        control ? ",\n    // or where the programs' control matrix Ā M⁻¹ D is singular" : "", set_names.size(),
        literal_list(set_names), orders, indent(body, 8));
}

}  // namespace

std::string emit_header(const KernelIR& ir, const EmitOptions& options) {
    const LocalNames names(ir);
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;

    std::vector<std::string> state_names, parameter_names;
    for (const auto& s : ir.state) state_names.push_back(s.name);
    for (const auto& s : ir.parameters) parameter_names.push_back(s.name);

    const Rates rates = emit_rates(ir, names);
    std::string includes = uses_kepler_solver(ir) ? fmt::format("#include <{}>\n", model::kepler_E_header) : "";
    includes += rates.includes;
    const std::string table = [&] {
        std::string t = table_row("mass_matrix", ir.mass_matrix) + table_row("forcing", ir.forcing) + rates.table +
                        table_row("invariants", ir.invariants);
        if (!ir.output_names.empty()) t += table_row("outputs", ir.outputs);
        if (!ir.event_names.empty()) t += table_row("events", ir.events);
        if (!ir.singular_set_names.empty()) t += table_row("singular_sets", ir.singular_sets);
        if (!ir.program_names.empty()) t += table_row("program residuals", ir.program_residuals);
        if (!ir.contact_names.empty())
            t += table_row("contact gaps", ir.contact_gaps) + table_row("contact jacobian", ir.contact_jacobian) +
                 table_row("contact bias", ir.contact_bias);
        if (!ir.contact_time_rates.outputs.empty()) t += table_row("contact time rates", ir.contact_time_rates);
        t.pop_back();
        return t;
    }();

    // What the runtime's drivers call after every accepted step: a quaternion renormalised, or
    // Encke's rectification.
    // A kernel with constraint rows prints its project() with them (constraints_part).
    std::string projection = ir.constraint_names.empty() ? unit_projection(ir) : std::string(),
                private_part = rates.private_part;
    if (ir.rectification && !ir.constraint_names.empty())
        throw std::runtime_error("a kernel with both constraint rows and a rectification");
    if (ir.rectification) {
        if (!projection.empty()) throw std::runtime_error("a kernel with both a unit quaternion and a rectification");
        const Rectification r = rectification(ir, names);
        projection = r.project;
        private_part += (private_part.empty() ? "\n private:\n" : "\n") + r.private_part;
        includes += "#include <eomc/runtime/orbit/encke.hpp>\n";
    }
    std::string variational;
    if (options.variational && !ir.has_jacobian)
        throw std::logic_error("variational_rhs needs jacobian(): lower the kernel with LowerOptions::jacobian");
    if (options.variational) {
        variational = variational_function(ir);
        includes += "#include <eomc/runtime/variational.hpp>\n";
    }

    const std::string solve_note = nu == 0 ? "Every rate is explicit."
                                   : straight_line_constraints(ir)
                                       ? "M u̇ − Wᵀλ = f, W u̇ = r is solved in straight-line code (LDLᵀ of [[M, Wᵀ], [W, 0]], the "
                                         "velocities first: the Schur complement), and so are the projection's corrections."
                                   : !ir.constraint_names.empty()
                                       ? "M u̇ − Wᵀλ = f, W u̇ = r is solved at run time (the Schur complement on Eigen's LDLT)."
                                   : straight_line_programs(ir)
                                       ? "M u̇ = f + D λ, Ā u̇ = c: z = M⁻¹f, Y = M⁻¹D, G = Ā Y and h = c − Ā z in straight-line "
                                         "code, G λ = h by LU with partial pivoting at run time. " +
                                             describe(ir.program_plan, nu)
                                   : !ir.program_names.empty()
                                       ? "M u̇ = f + D λ, Ā u̇ = c is solved at run time (runtime/program/control.hpp)."
                                   : ir.explicit_solution ? "u̇ is solved in closed form (n_velocities ≤ 2)."
                                                        : describe(ir.solve_plan, nu);
    const std::string jacobian_note = ir.has_jacobian ? "jacobian() gives ∂ẋ/∂x."
                                                      : "No jacobian() (eomc generate --jacobian adds it).";
    const std::vector<std::pair<std::string, std::string>> fields{
        {"version", options.generator_version},
        {"source", comment_text(ir.source)},
        {"summary", comment_text(ir.summary.empty() ? ir.scene_name : ir.summary)},
        {"description", comment(ir.description + " " + solve_note + " " + jacobian_note)},
        {"operation_table", table},
        {"includes", includes},
        {"runtime_version", "1"},
        {"struct_name", checked_identifier(ir.struct_name, "the kernel's name")},
        {"scene_name", checked_identifier(ir.scene_name, "the scene name")},
        {"n", std::to_string(ir.n_coordinates)},
        {"n_state", std::to_string(N)},
        {"velocity_offset", std::to_string(ir.velocity_offset)},
        {"n_velocities", std::to_string(nu)},
        {"n_parameters", std::to_string(ir.parameters.size())},
        {"n_invariants", std::to_string(ir.invariant_names.size())},
        {"n_outputs", std::to_string(ir.output_names.size())},
        {"separable", ir.separable ? "true" : "false"},
        // Straight-line rates: nothing solved by a library at run time (a closed form, or a solve
        // unrolled from M's structure), no iteration (Kepler's equation), no rows.
        {"batchable", (nu == 0 || ir.explicit_solution || straight_line_solve(ir.solve_plan)) &&
                              ir.constraint_names.empty() && ir.program_names.empty() &&
                              ir.contact_names.empty() && !ir.rectification && !uses_kepler_solver(ir)
                          ? "true"
                          : "false"},
        {"state_names", quoted_list(state_names, "a state name")},
        {"parameter_names", quoted_list(parameter_names, "a parameter name")},
        {"invariant_names", quoted_list(ir.invariant_names, "an invariant name")},
        {"output_names", quoted_list(ir.output_names, "an output name")},
        {"initial_state", number_list(ir.initial_state, "an initial value")},
        {"parameter_members", parameter_members(ir, names)},
        {"mass_matrix_body", indent(block_body(ir, names, ir.mass_matrix, "out"), 8)},
        {"forcing_body", indent(block_body(ir, names, ir.forcing, "out"), 8)},
        {"rhs_body", indent(rates.rhs, 8)},
        {"has_jacobian", ir.has_jacobian ? "true" : "false"},
        {"jacobian", ir.has_jacobian ? jacobian_function(rates.jacobian) : std::string()},
        {"invariants_body", indent(block_body(ir, names, ir.invariants, "out"), 8)},
        {"outputs_note", ir.output_names.empty() ? "none for this model" : "functions of t, x and u̇"},
        {"outputs_body", indent(outputs_body(ir, names), 8)},
        {"acceleration", acceleration_function(ir)},
        {"events", events_part(ir, names)},
        {"constraints", constraints_part(ir) + contacts_part(ir, names) + programs_part(ir)},
        {"variational", projection + variational},
        {"invariant_accessors",
         invariant_accessors(ir) + santilli_residuals(ir, names) + singular_sets_part(ir, names)},
        {"private_part", private_part},
    };
    return fill_template(kernel_template(), fields);
}

std::string emit_reference_body(const KernelIR& ir, const std::vector<GiNaC::ex>& reference) {
    if (reference.size() != ir.state.size())
        throw std::runtime_error(fmt::format("the reference has {} values for {} state variables", reference.size(),
                                             ir.state.size()));
    Block block;
    block.outputs = reference;
    Inputs inputs;
    inputs.state_array = false;
    return function_body(ir, LocalNames(ir), block, indexed("out", reference.size()), inputs);
}

}  // namespace eomc::codegen
