// CppExpressionPrinter (cpp_emitter.hpp): one GiNaC expression as C++ over the scalar type S.
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "model/functions.hpp"
#include "model/kepler_function.hpp"

namespace eomc::codegen {

using GiNaC::ex;
using GiNaC::numeric;

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
        // Appended piece by piece: "/" + ("(" + den + ")") trips GCC 12's -Wrestrict (a false positive).
        const bool grouped = denominator.size() > 1;
        out += grouped ? "/(" : "/";
        out += den;
        if (grouped) out += ")";
    }
    return out;
}

std::string CppExpressionPrinter::print_power(const ex& base, const numeric& k) {
    // numeric::to_long() is exact only inside long's range; an exponent beyond 2^53 would not
    // even print exactly as a floating literal.
    if (k.is_integer() && !small_integer(k))
        throw EmitError(fmt::format("the exponent {} is too large to emit", comment_text(printed_numeric(k))));
    if (!multiplied_power(k)) {
        functions_.insert("pow");
        return "pow(" + print(base, sum) + ", " + (k.is_integer() ? fmt::format("S({})", k.to_long()) : print_numeric(k)) +
               ")";
    }
    // |k| = m or m + 1/2: binary powering of the base, times sqrt(base) for the half.
    const bool half = !k.is_integer();
    const numeric magnitude = GiNaC::abs(k);
    const unsigned long m = static_cast<unsigned long>((half ? magnitude - numeric(1, 2) : magnitude).to_long());
    std::string text = m > 0 ? powering(print(base, atom), m) : "";
    if (half) {
        if (!text.empty()) text += "*";
        text += call("sqrt", print(base, sum));
    }
    if (!k.is_negative()) return text;
    // Appended piece by piece: "S(1)/(" + text + ")" trips GCC 12's -Wrestrict (a false positive).
    std::string quotient = "S(1)/";
    const bool single = half ? m == 0 : m == 1;  // one factor: x or sqrt(x)
    if (!single) quotient += "(";
    quotient += text;
    if (!single) quotient += ")";
    return quotient;
}

// b^m (m ≥ 1) by binary powering: the square of b^(m/2), times b when m is odd. The repeated
// text of b^(m/2) is one value to the compiler (the same operation on the same operands).
std::string CppExpressionPrinter::powering(const std::string& b, unsigned long m) {
    if (m == 1) return b;
    const std::string root = powering(b, m / 2);
    const std::string grouped = root.find('*') == std::string::npos ? root : "(" + root + ")";
    std::string text = grouped + "*" + grouped;
    return m % 2 == 1 ? text + "*" + b : text;
}

}  // namespace eomc::codegen
