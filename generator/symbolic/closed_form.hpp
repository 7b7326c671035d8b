// Closed-form roots of a system of equations in a few unknowns, knowing no mechanics: each
// equation is factored (sin x and cos x of every unknown taken as variables), and factors in one
// unknown of the forms a x + b, a x² + b x + c, a sin x + b, a cos x + b, a cos² x + b cos x + c and
// a sin x + b cos x are solved and substituted into the remaining equations. The equilibria of
// chapter 1 (relative rest) and chapter 6 (the KKT conditions on an active set) both solve with it.
#pragma once

#include <optional>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::symbolic {

// sin x_k and cos x_k as polynomial variables, so that factor() splits products of them.
struct TrigVariables {
    GiNaC::exmap to_variables, to_functions;
    std::vector<GiNaC::symbol> sin_of, cos_of;  // per unknown
    explicit TrigVariables(const std::vector<GiNaC::symbol>& unknowns);
};

// A root x* with sin x* and cos x* in closed form, so that substituting it leaves algebra
// (no cos(−acos x) for GiNaC to puzzle over).
struct Root {
    GiNaC::ex q, sin, cos;
};

struct ClosedForm {
    std::vector<Root> q;          // per unknown
    std::vector<bool> periodic;   // per unknown: its value came through sin/cos (x + 2πk are roots too)
    GiNaC::exmap substitution;    // x_k, sin x_k, cos x_k → their closed forms (equations in TrigVariables)
};

// The value of a closed form with `values` substituted (the parameters' defaults); nullopt when
// it is not real there (asin/acos of an argument beyond ±1, the square root of a negative
// discriminant).
std::optional<double> real_value(const GiNaC::exmap& values, const GiNaC::ex& e);

class ClosedFormSolver {
public:
    // `defaults` decides conditions on the parameters alone (a branch lives only where they hold).
    ClosedFormSolver(std::vector<GiNaC::symbol> unknowns, const TrigVariables& trig, GiNaC::exmap defaults)
        : unknowns_(std::move(unknowns)), trig_(trig), defaults_(std::move(defaults)) {}

    // Every closed-form solution of f = 0 (f in TrigVariables); `complete` false when some
    // branch could not be solved (a factor of no form solved here, a continuum, too many
    // branches). Elimination goes through numerators, so a solution may be spurious where a
    // denominator vanishes: the caller checks each one numerically. Unknowns marked free are
    // held at 0. An equation is solved for the first of its unknowns (in the given order) that
    // one of the forms above isolates.
    std::vector<ClosedForm> solve(const std::vector<GiNaC::ex>& f, const std::vector<bool>& free, bool& complete);

private:
    std::vector<std::size_t> unknowns_in(const GiNaC::ex& e, const GiNaC::exmap& solved) const;
    GiNaC::ex reduce(const GiNaC::ex& e, const GiNaC::exmap& solved) const;
    void branch(const std::vector<GiNaC::ex>& f, const std::vector<bool>& done, const ClosedForm& partial);
    ClosedForm with(const ClosedForm& partial, std::size_t k, const Root& root, bool periodic) const;
    bool holds_at_defaults(const GiNaC::ex& e) const;

    std::vector<GiNaC::symbol> unknowns_;
    const TrigVariables& trig_;
    GiNaC::exmap defaults_;
    std::vector<ClosedForm> solutions_;
    bool* complete_ = nullptr;
};

}  // namespace eomc::symbolic
