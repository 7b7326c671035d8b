#include "model/kepler_function.hpp"

#include <stdexcept>

#include "eomc/runtime/orbit/kepler.hpp"

namespace eomc::model {

using GiNaC::ex;

namespace {

ex kepler_E_evalf(const ex& M, const ex& e) {
    if (!GiNaC::is_a<GiNaC::numeric>(M) || !GiNaC::is_a<GiNaC::numeric>(e)) return kepler_E(M, e).hold();
    const auto& m = GiNaC::ex_to<GiNaC::numeric>(M);
    const auto& x = GiNaC::ex_to<GiNaC::numeric>(e);
    if (!m.is_real() || !x.is_real()) return kepler_E(M, e).hold();
    return GiNaC::numeric(kepler_E_value(m.to_double(), x.to_double()));
}

ex kepler_E_eval(const ex& M, const ex& e) {
    if (e.is_zero() || M.is_zero()) return M;  // E = M on a circle and at periapsis
    return kepler_E(M, e).hold();
}

ex kepler_E_derivative(const ex& M, const ex& e, unsigned which) {
    const ex E = kepler_E(M, e);
    return which == 0 ? kepler_E_partial_M(E, e) : kepler_E_partial_e(E, e);
}

void kepler_E_print_latex(const ex& M, const ex& e, const GiNaC::print_context& c) {
    c.s << "E(";
    M.print(c);
    c.s << ", ";
    e.print(c);
    c.s << ")";
}

}  // namespace

REGISTER_FUNCTION(kepler_E, eval_func(kepler_E_eval)
                                .evalf_func(kepler_E_evalf)
                                .derivative_func(kepler_E_derivative)
                                .print_func<GiNaC::print_latex>(kepler_E_print_latex))

ex kepler_E_partial_M(const ex& E, const ex& e) { return 1 / (1 - e * GiNaC::cos(E)); }

ex kepler_E_partial_e(const ex& E, const ex& e) { return GiNaC::sin(E) / (1 - e * GiNaC::cos(E)); }

bool has_kepler_E(const ex& e) { return e.has(kepler_E(GiNaC::wild(0), GiNaC::wild(1))); }

double kepler_E_value(double M, double e) {
    try {
        return runtime::eccentric_from_mean(M, e);
    } catch (const std::exception& error) {
        throw std::domain_error(error.what());
    }
}

}  // namespace eomc::model
