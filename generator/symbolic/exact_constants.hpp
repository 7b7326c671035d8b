// Constants a double cannot carry. A scene may write sin(10^300) or cos(pi*10^20): exact
// numbers whose nearest double lies many periods away from them, so a kernel that evaluates
// the function on the double argument (as C++ must) computes an unrelated value, and GiNaC's
// evalf at its default 17 digits returns rounding noise. Such constants are evaluated here in
// CLN at increasing precision until two evaluations agree, and replaced by their value.
#pragma once

#include <stdexcept>
#include <string>

#include <ginac/ginac.h>

namespace eomc::symbolic {

// A constant that has no finite real value within double's range, or that does not settle by
// the largest precision tried; what() names the constant.
struct ConstantOutOfReach : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The exact value of a constant expression (no symbols) as a CLN float of `digits` decimal
// digits, from evaluations at 40, 80, 160, ... digits until two successive ones agree to
// `digits` (at most 20 000 digits: sin(10^300) needs about 330). Throws ConstantOutOfReach when
// it is not real and finite, or does not settle.
GiNaC::numeric exact_value(const GiNaC::ex& constant, int digits = 40);

// e with each constant function call or power f(a) (all arguments exact numbers or constants
// such as pi) whose value at the arguments rounded to double differs from its exact value by
// more than a few units in the last place of a double replaced by the nearest double to its
// exact value. Well-conditioned constants (cos(2), exp(1/3), sqrt(2)) are left alone, so a
// float128 kernel still evaluates them in its own precision. Throws ConstantOutOfReach for a
// constant call beyond double's range (exp(10^4)) or without a real value, and for a number that
// is not real (GiNaC writes log(-2) as log(2) + I·π).
GiNaC::ex fold_ill_conditioned_constants(const GiNaC::ex& e);

}  // namespace eomc::symbolic
