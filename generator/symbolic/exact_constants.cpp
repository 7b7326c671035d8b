#include "symbolic/exact_constants.hpp"

#include <cln/float.h>
#include <cln/real.h>
#include <cln/rational.h>

#include <cfloat>
#include <cmath>
#include <optional>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

namespace eomc::symbolic {

using GiNaC::ex;
using GiNaC::numeric;

namespace {

// GiNaC's working precision is a global: set for one evaluation, restored on every exit.
class Precision {
public:
    explicit Precision(long digits) : saved_(GiNaC::Digits) { GiNaC::Digits = digits; }
    ~Precision() { GiNaC::Digits = saved_; }
    Precision(const Precision&) = delete;
    Precision& operator=(const Precision&) = delete;

private:
    long saved_;
};

std::string text_of(const ex& e) {
    std::ostringstream s;
    s << e;
    std::string out = s.str();
    return out.size() > 200 ? out.substr(0, 200) + "…" : out;
}

// No symbol anywhere: numbers and GiNaC's constants (pi, Euler's) only.
bool is_constant(const ex& e) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) return false;
    for (std::size_t i = 0; i < e.nops(); ++i)
        if (!is_constant(e.op(i))) return false;
    return true;
}

std::optional<numeric> evaluated(const ex& e, long digits) {
    const Precision at(digits);
    ex v;
    try {
        v = e.evalf();
    } catch (const std::exception&) {  // a pole, an overflow inside CLN
        return std::nullopt;
    }
    if (!GiNaC::is_a<numeric>(v) || !GiNaC::ex_to<numeric>(v).is_real()) return std::nullopt;
    return GiNaC::ex_to<numeric>(v);
}

double nearest_double(const numeric& v, const ex& what) {
    const double d = v.to_double();
    if (!std::isfinite(d))
        throw ConstantOutOfReach(fmt::format("the constant {} is outside the range of double (its magnitude exceeds "
                                             "{:.6g})",
                                             text_of(what), DBL_MAX));
    return d;
}

// A double's exact binary value as a rational: GiNaC keeps f(rational) unevaluated, where it
// would evaluate f on a float at once, in the float's own precision.
numeric exact_rational(double d) { return numeric(cln::rational(cln::cl_DF(d))); }

// Folds bottom-up: the arguments first, so a call sees its arguments as the kernel would.
// Memoized: a derived expression shares subtrees, and a walk of the tree would visit each once
// per path to it.
struct Folder : GiNaC::map_function {
    std::unordered_map<ex, ex> done;

    ex operator()(const ex& e) override {
        if (GiNaC::is_a<numeric>(e) && !GiNaC::ex_to<numeric>(e).is_real())
            throw ConstantOutOfReach("the constant " + text_of(e) + " is not real (from an expression such as log(-2) "
                                     "or sqrt(-1))");
        if (GiNaC::is_a<numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::constant>(e)) return e;
        if (const auto it = done.find(e); it != done.end()) return it->second;
        const ex folded = fold(e);
        done.emplace(e, folded);
        return folded;
    }

    ex fold(const ex& e) {
        const ex mapped = e.map(*this);
        const bool call = GiNaC::is_a<GiNaC::function>(mapped) || GiNaC::is_a<GiNaC::power>(mapped);
        if (!call || !is_constant(mapped)) return mapped;
        const numeric exact = exact_value(mapped);
        (void)nearest_double(exact, mapped);  // a constant beyond double's range is refused, not left to be inf
        // The call on its arguments rounded to double, as the kernel evaluates it.
        struct ToDouble : GiNaC::map_function {
            ex operator()(const ex& arg) override {
                if (GiNaC::is_a<numeric>(arg) && GiNaC::ex_to<numeric>(arg).is_integer() &&
                    GiNaC::abs(GiNaC::ex_to<numeric>(arg)) <= numeric(1L << 53))
                    return arg;  // exact in double
                return exact_rational(nearest_double(exact_value(arg), arg));
            }
        } to_double;
        const ex rounded = mapped.map(to_double);
        const numeric on_doubles = exact_value(rounded);
        const numeric tolerance = numeric(4) * numeric(DBL_EPSILON) * GiNaC::abs(exact);
        if (GiNaC::abs(on_doubles - exact) <= tolerance) return mapped;
        return numeric(nearest_double(exact, mapped));
    }
};

}  // namespace

numeric exact_value(const ex& constant, int digits) {
    if (GiNaC::is_a<numeric>(constant) && GiNaC::ex_to<numeric>(constant).is_rational())
        return GiNaC::ex_to<numeric>(constant);
    std::optional<numeric> previous;
    constexpr long most_digits = 20000;
    for (long d = 40; d <= most_digits; d *= 2) {
        const std::optional<numeric> v = evaluated(constant, d + digits);
        if (!v)
            throw ConstantOutOfReach("the constant " + text_of(constant) + " has no real value");
        // Two evaluations that agree settle the value. Zero does not: a float argument whose unit
        // in the last place exceeds 2π gives sin 0.0 at every precision too low to hold it, so
        // a zero is believed only at the largest precision (an exact zero GiNaC finds itself).
        if (previous && !v->is_zero()) {
            const Precision at(d + digits);
            const numeric bound = GiNaC::abs(*v) / GiNaC::pow(numeric(10), numeric(digits));
            if (GiNaC::abs(*v - *previous) <= bound) return *v;
        }
        if (v->is_zero() && previous && previous->is_zero() && d * 2 > most_digits) return *v;
        previous = v;
    }
    throw ConstantOutOfReach("the constant " + text_of(constant) + " does not settle to a value at 20000 digits");
}

ex fold_ill_conditioned_constants(const ex& e) {
    Folder folder;
    return folder(e);
}

}  // namespace eomc::symbolic
