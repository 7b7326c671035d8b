#include "model/expression_parser.hpp"

#include <cctype>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "model/functions.hpp"
#include "support/diagnostic.hpp"
#include "support/identifier.hpp"

namespace eomc::model {

namespace {

bool ident_start(char c) { return is_ascii_letter(c) || c == '_'; }
bool ident_char(char c) { return is_ascii_word_char(c); }
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

// A decimal literal as its digits and power of ten: "1.25e-3" -> {"125", -5}. The exponent is
// read only while it stays below `exponent_cap` in magnitude (the literal is refused beyond).
struct Decimal {
    std::string digits;  // no leading zeros ("0" for zero)
    long exponent = 0;
    bool exponent_overflow = false;
};

Decimal split_decimal(const std::string& lit, long exponent_cap) {
    Decimal d;
    std::string mantissa = lit;
    if (auto e = lit.find_first_of("eE"); e != std::string::npos) {
        mantissa = lit.substr(0, e);
        std::size_t k = e + 1;
        const bool negative = k < lit.size() && lit[k] == '-';
        if (k < lit.size() && (lit[k] == '+' || lit[k] == '-')) ++k;
        for (; k < lit.size(); ++k) {
            d.exponent = d.exponent * 10 + (lit[k] - '0');
            if (d.exponent > exponent_cap) {
                d.exponent_overflow = true;
                break;
            }
        }
        if (negative) d.exponent = -d.exponent;
    }
    for (char c : mantissa)
        if (c != '.') d.digits += c;
    if (auto dot = mantissa.find('.'); dot != std::string::npos) d.exponent -= long(mantissa.size() - dot - 1);
    d.digits.erase(0, std::min(d.digits.find_first_not_of('0'), d.digits.size() - 1));
    return d;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The functions a scene may call (model/functions.hpp), and sqrt.
const std::map<std::string, std::function<GiNaC::ex(const GiNaC::ex&)>>& callable() {
    static const std::map<std::string, std::function<GiNaC::ex(const GiNaC::ex&)>> table{
        {"sin", [](const GiNaC::ex& x) { return GiNaC::sin(x); }},
        {"cos", [](const GiNaC::ex& x) { return GiNaC::cos(x); }},
        {"tan", [](const GiNaC::ex& x) { return GiNaC::tan(x); }},
        {"exp", [](const GiNaC::ex& x) { return GiNaC::exp(x); }},
        {"log", [](const GiNaC::ex& x) { return GiNaC::log(x); }},
        {"asin", [](const GiNaC::ex& x) { return GiNaC::asin(x); }},
        {"acos", [](const GiNaC::ex& x) { return GiNaC::acos(x); }},
        {"atan", [](const GiNaC::ex& x) { return GiNaC::atan(x); }},
        {"sinh", [](const GiNaC::ex& x) { return GiNaC::sinh(x); }},
        {"cosh", [](const GiNaC::ex& x) { return GiNaC::cosh(x); }},
        {"tanh", [](const GiNaC::ex& x) { return GiNaC::tanh(x); }},
        {"sqrt", [](const GiNaC::ex& x) { return GiNaC::sqrt(x); }},
    };
    return table;
}

// The exact limits of double's normal range: a literal outside it could never be emitted.
const GiNaC::numeric& double_max() {
    static const GiNaC::numeric value = (GiNaC::numeric(2).power(53) - 1) * GiNaC::numeric(2).power(971);
    return value;
}
const GiNaC::numeric& double_min() {
    static const GiNaC::numeric value = GiNaC::numeric(2).power(-1022);
    return value;
}

std::size_t bit_length(const GiNaC::numeric& integer) {
    return integer.is_zero() ? 0 : std::size_t(GiNaC::numeric(GiNaC::abs(integer)).int_length());
}

// The bits of the numbers a power would raise when `e` is its base: a number, and the numeric
// factors of a product, a power of a number counting as its base's bits times its exponent.
GiNaC::numeric number_bits(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
        const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
        if (!n.is_rational() || GiNaC::abs(n) == 1) return 0;  // ±1 raised is ±1
        return long(std::max(bit_length(n.numer()), bit_length(n.denom())));
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(0)) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
        const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
        return k.is_rational() ? number_bits(e.op(0)) * GiNaC::abs(k) : GiNaC::numeric(0);
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
        GiNaC::numeric sum = 0;
        for (const GiNaC::ex& factor : e) sum += number_bits(factor);
        return sum;
    }
    return 0;
}

// One expression, by recursive descent over
//   sum     := product { ('+' | '-') product }
//   product := signed { ('*' | '/') signed }
//   signed  := ('+' | '-') signed | power
//   power   := primary [ '^' exponent ]        (a^b^c is refused: write the parentheses)
//   exponent:= ('+' | '-') exponent | primary
//   primary := number | name | function '(' sum ')' | '(' sum ')'
// so that −x² is −(x²) and x^-2 is x^(−2), as in GiNaC's own parser, which this replaces
// because it reports no position, has no depth limit, crashes on "sin()", and binds names
// of its own (I, Euler, Catalan) before the scene's.
class Parser {
public:
    Parser(const SymbolTable& table, const std::map<std::string, SymbolKind>& kinds, const scene::Expr& expr,
           unsigned allowed, const std::string& what)
        : table_(table), kinds_(kinds), expr_(expr), text_(expr.text), allowed_(allowed), what_(what) {}

    GiNaC::ex parse() {
        if (text_.size() > max_expression_length)
            fail(0, fmt::format("the expression is {} characters long; at most {} are accepted", text_.size(),
                                max_expression_length));
        skip_space();
        if (at_ == text_.size()) throw InputError(expr_.pos, fmt::format("empty expression for {}", what_));
        GiNaC::ex e = sum();
        if (at_ != text_.size()) fail(at_, fmt::format("unexpected {}", describe_here()));
        return e;
    }

private:
    [[noreturn]] void fail(std::size_t offset, const std::string& detail) const {
        throw InputError(expr_.pos.shifted(int(offset)), fmt::format("cannot parse {} '{}': {}", what_, text_, detail));
    }

    // GiNaC's arithmetic throws on 1/0, 0^0, log(0), tan(π/2), and leaks the object it was
    // building when it does: those cases are refused before GiNaC sees them (undefined()),
    // and anything else it throws is still an error at the operator. A value that comes out
    // complex (sqrt(-1) is GiNaC's I) is no value of a real scene.
    template <class F>
    GiNaC::ex evaluated(std::size_t op, F&& f) const {
        GiNaC::ex value;
        try {
            value = f();
        } catch (const std::exception& e) {
            fail(op, fmt::format("the value is undefined ({})", e.what()));
        }
        if (GiNaC::is_a<GiNaC::numeric>(value) && !GiNaC::ex_to<GiNaC::numeric>(value).is_real())
            fail(op, "the value is not real");
        return value;
    }

    static bool is_numeric_zero(const GiNaC::ex& e) { return GiNaC::is_a<GiNaC::numeric>(e) && e.is_zero(); }

    // The reason GiNaC would throw on base^exponent, f(argument) or a/b, or nullptr.
    static const char* undefined_power(const GiNaC::ex& base, const GiNaC::ex& exponent) {
        if (!is_numeric_zero(base) || !GiNaC::is_a<GiNaC::numeric>(exponent)) return nullptr;
        const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
        if (k.is_zero()) return "0^0 is undefined";
        if (k.is_negative()) return "a negative power of 0 is undefined";
        return nullptr;
    }
    static const char* undefined_call(const std::string& function, const GiNaC::ex& argument) {
        if (function == "log" && is_numeric_zero(argument)) return "log(0) is undefined";
        if (function == "tan") {  // GiNaC finds the pole at odd multiples of π/2
            const GiNaC::ex ratio = argument / GiNaC::Pi;
            if (GiNaC::is_a<GiNaC::numeric>(ratio) && ratio.info(GiNaC::info_flags::rational) &&
                GiNaC::ex_to<GiNaC::numeric>(ratio).denom() == 2)
                return "tan is undefined at odd multiples of π/2";
        }
        return nullptr;
    }

    void skip_space() {
        while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    }
    bool peek(char c) const { return at_ < text_.size() && text_[at_] == c; }
    std::string describe_here() const {
        if (at_ >= text_.size()) return "end of expression";
        const unsigned char c = static_cast<unsigned char>(text_[at_]);
        if (c < 0x20 || c >= 0x7F) return fmt::format("character 0x{:02X}", unsigned(c));
        return fmt::format("'{}'", text_[at_]);
    }

    // Each nested parenthesis, call, sign or exponent is one level: the recursion (and the work
    // of differentiating a deep expression) stays bounded.
    struct Level {
        explicit Level(Parser& p) : p_(p) {
            if (++p_.depth_ > max_expression_depth)
                p_.fail(p_.at_, fmt::format("nested more than {} levels deep", max_expression_depth));
        }
        ~Level() { --p_.depth_; }
        Parser& p_;
    };

    GiNaC::ex sum() {
        GiNaC::ex e = product();
        for (skip_space(); peek('+') || peek('-'); skip_space()) {
            const std::size_t op = at_;
            const bool minus = text_[at_++] == '-';
            const GiNaC::ex rhs = product();
            e = evaluated(op, [&] { return minus ? e - rhs : e + rhs; });
        }
        return e;
    }

    GiNaC::ex product() {
        GiNaC::ex e = signed_term();
        for (skip_space(); (peek('*') || peek('/')); skip_space()) {
            const std::size_t op = at_;
            const bool divide = text_[at_++] == '/';
            if (!divide && peek('*')) fail(op, "'**' is not an operator; write powers with '^'");
            const GiNaC::ex rhs = signed_term();
            if (divide && is_numeric_zero(rhs)) fail(op, "the value is undefined (division by zero)");
            e = evaluated(op, [&] { return divide ? e / rhs : e * rhs; });
        }
        return e;
    }

    GiNaC::ex signed_term() {
        skip_space();
        if (peek('-') || peek('+')) {
            const bool minus = text_[at_++] == '-';
            Level level(*this);
            const GiNaC::ex e = signed_term();
            return minus ? -e : e;
        }
        return power();
    }

    // A signed primary: the exponent of a power, which takes no power of its own.
    GiNaC::ex exponent_term() {
        skip_space();
        if (peek('-') || peek('+')) {
            const bool minus = text_[at_++] == '-';
            Level level(*this);
            const GiNaC::ex e = exponent_term();
            return minus ? -e : e;
        }
        return primary();
    }

    GiNaC::ex power() {
        GiNaC::ex base = primary();
        skip_space();
        if (!peek('^')) return base;
        const std::size_t op = at_++;
        Level level(*this);
        const GiNaC::ex exponent = exponent_term();
        skip_space();
        if (peek('^')) fail(at_, "a^b^c is ambiguous; write a^(b^c) or (a^b)^c");
        return checked_power(base, exponent, op);
    }

    // GiNaC evaluates a power of numbers exactly: 10^(10^9) would run for minutes. An
    // exponent must also be one the emitter can write (|n| ≤ 2^53).
    GiNaC::ex checked_power(const GiNaC::ex& base, const GiNaC::ex& exponent, std::size_t op) const {
        if (GiNaC::is_a<GiNaC::numeric>(exponent)) {
            const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
            if (!k.is_rational()) fail(op, "the exponent is not a real rational number");
            const GiNaC::numeric limit = GiNaC::numeric(2).power(53);
            if (GiNaC::abs(k.numer()) > limit || k.denom() > limit)
                fail(op, "the exponent is too large (numerator and denominator must not exceed 2^53)");
            // GiNaC raises every number in the base: 10^k, and also (10·m)^k = 10^k·m^k and
            // (√2·m)^k = 2^(k/2)·m^k. The exact result has about |k|·bits bits; beyond the cap it
            // is no physical constant.
            const GiNaC::numeric bits = number_bits(base);
            if (GiNaC::abs(k) * bits > GiNaC::numeric(long(max_power_bits)))
                fail(op, fmt::format("the power of numbers would have more than {} bits", max_power_bits));
        }
        if (const char* why = undefined_power(base, exponent)) fail(op, fmt::format("the value is undefined ({})", why));
        return evaluated(op, [&] { return GiNaC::pow(base, exponent); });
    }

    GiNaC::ex primary() {
        skip_space();
        if (at_ == text_.size()) fail(at_, "expected a number, a name or '(' at the end of the expression");
        const char c = text_[at_];
        if (c == '(') {
            const std::size_t open = at_++;
            Level level(*this);
            GiNaC::ex e = sum();
            skip_space();
            if (!peek(')')) fail(at_, fmt::format("expected ')' to close the '(' at column {}, found {}",
                                                  expr_.pos.shifted(int(open)).column, describe_here()));
            ++at_;
            return e;
        }
        if (const std::size_t n = number_length(text_, at_); n > 0) return number(n);
        if (ident_start(c)) return name();
        fail(at_, fmt::format("expected a number, a name or '(', found {}", describe_here()));
    }

    // "0.25" -> 1/4 exactly, so that the algebra stays exact and every machine prints the same
    // constants; within double's normal range, as the emitted code must hold it.
    GiNaC::ex number(std::size_t n) {
        const std::size_t start = at_;
        const std::string lit = text_.substr(at_, n);
        at_ += n;
        if (lit.size() > max_literal_length)
            fail(start, fmt::format("a number of more than {} characters", max_literal_length));
        const Decimal d = split_decimal(lit, 100000);
        GiNaC::numeric value(d.digits.c_str());
        if (value.is_zero()) return value;
        const long magnitude = long(d.digits.size()) - 1 + d.exponent;  // value = x.yyy · 10^magnitude
        if (d.exponent_overflow || magnitude > 400 || magnitude < -400)
            fail(start, fmt::format("the number {} lies outside the range of double", lit));
        value *= GiNaC::numeric(10).power(d.exponent);
        if (value > double_max() || value < double_min())
            fail(start, fmt::format("the number {} lies outside the range of double", lit));
        return value;
    }

    GiNaC::ex name() {
        const std::size_t start = at_;
        while (at_ < text_.size() && ident_char(text_[at_])) ++at_;
        const std::string id = text_.substr(start, at_ - start);
        const SourcePos where = expr_.pos.shifted(int(start));
        skip_space();
        if (peek('(')) return call(id, start, where);
        if (id == "Pi") return GiNaC::Pi;
        auto it = kinds_.find(id);
        if (it == kinds_.end()) {
            for (const char* suffix : {"_ddot", "_dot"}) {
                if (ends_with(id, suffix)) {
                    const std::string base = id.substr(0, id.size() - std::string(suffix).size());
                    if (!kinds_.count(base) || kinds_.at(base) != SymbolKind::coordinate)
                        throw InputError(where, fmt::format("unknown symbol '{}' in {}: '{}' is not a declared coordinate",
                                                            id, what_, base));
                }
            }
            std::vector<std::string> names;
            for (const auto& [n, k] : kinds_) names.push_back(n);
            const std::string near = nearest_name(id, names);
            throw InputError(where, fmt::format("unknown symbol '{}' in {}{}", id, what_,
                                                near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (!(unsigned(it->second) & allowed_))
            throw InputError(where, fmt::format("'{}' is {}, which may not appear in {}", id, describe(it->second), what_));
        return table_.symbol(id);
    }

    GiNaC::ex call(const std::string& id, std::size_t start, const SourcePos& where) {
        const auto& functions = callable();
        const auto f = functions.find(id);
        if (f == functions.end()) {
            std::vector<std::string> names;
            for (const auto& [n, fn] : functions) names.push_back(n);
            const std::string near = nearest_name(id, names);
            throw InputError(where, fmt::format("unknown function '{}' in {}{}", id, what_,
                                                near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        ++at_;  // '('
        Level level(*this);
        skip_space();
        if (peek(')')) fail(at_, fmt::format("'{}' takes one argument, and none was given", id));
        const GiNaC::ex argument = sum();
        skip_space();
        if (peek(',')) fail(at_, fmt::format("'{}' takes one argument", id));
        if (!peek(')'))
            fail(at_, fmt::format("expected ')' to close the call of '{}' at column {}, found {}", id,
                                  expr_.pos.shifted(int(start)).column, describe_here()));
        ++at_;
        if (const char* why = undefined_call(id, argument)) fail(start, fmt::format("the value is undefined ({})", why));
        return evaluated(start, [&] { return f->second(argument); });
    }

    const SymbolTable& table_;
    const std::map<std::string, SymbolKind>& kinds_;
    const scene::Expr& expr_;
    const std::string& text_;
    unsigned allowed_;
    const std::string& what_;
    std::size_t at_ = 0;
    int depth_ = 0;
};

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
    if (auto it = symbols_.find(name); it != symbols_.end()) return it->second;
    GiNaC::symbol s(name, tex_name(name, kind));
    symbols_.emplace(name, s);
    kinds_[name] = kind;
    return s;
}

const GiNaC::symbol& SymbolTable::symbol(const std::string& name) const { return symbols_.at(name); }

GiNaC::ex SymbolTable::parse(const scene::Expr& expr, unsigned allowed, const std::string& what) const {
    return Parser(*this, kinds_, expr, allowed, what).parse();
}

}  // namespace eomc::model
