// Stage 5: kernel IR → one self-contained C++ header (templates/kernel.hpp.in).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "codegen/canonical_order.hpp"
#include "codegen/kernel_ir.hpp"

namespace eomc::codegen {

// Prints one GiNaC expression as C++ over a scalar type S, through a visitor with one
// case per node kind; anything it does not know how to emit is an error, never a guess.
class CppExpressionPrinter {
public:
    explicit CppExpressionPrinter(std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names)
        : names_(std::move(names)) {}
    std::string print(const GiNaC::ex& e);
    // std:: functions the printed code called (for `using std::sin;` lines, so that other
    // scalar types find their overloads by argument-dependent lookup).
    const std::set<std::string>& functions_used() const { return functions_; }

private:
    enum Precedence { sum = 1, product = 2, unary = 3, atom = 4 };
    std::string print(const GiNaC::ex& e, Precedence context);
    std::string print_add(const GiNaC::ex& e);
    std::string print_mul(const GiNaC::ex& e);
    std::string print_power(const GiNaC::ex& base, const GiNaC::numeric& exponent);
    std::string powering(const std::string& base, unsigned long m);
    std::string print_numeric(const GiNaC::numeric& x);
    std::string call(const std::string& function, const std::string& argument);

    std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names_;
    std::set<std::string> functions_;
    CanonicalOrder order_;
};

struct EmitOptions {
    std::string generator_version;
    // Also emit variational_rhs: the state extended by the state-transition matrix
    // (runtime/variational.hpp; Hairer, Nørsett, Wanner I, Sect. I.14).
    bool variational = false;
};

// The whole header. Same IR, same bytes.
std::string emit_header(const KernelIR& ir, const EmitOptions& options);

// The body of `template <class S> void f(S t, S* out, const Parameters& p)` writing a closed-form
// reference solution (model::Model::reference, one expression of t and the parameters per state
// variable, in state order) into out[0..n_state), with the header's names for the parameters.
std::string emit_reference_body(const KernelIR& ir, const std::vector<GiNaC::ex>& reference);

}  // namespace eomc::codegen
