// Evaluation of expressions at reproducible pseudo-random points: how the generator decides
// questions that exact simplification cannot always settle (is M singular, is a quantity
// conserved) without guessing. The same seed gives the same points on every machine.
//
// Evaluation is in double precision by a walk over the expression DAG (each shared node
// once), not by GiNaC's subs + evalf, which is arbitrary-precision and far slower; time
// derivatives along a motion are taken in forward mode (dual numbers), not symbolically.
// Where double cannot settle a question (a residual that must vanish identically while its
// terms cancel over many orders of magnitude), the same point is evaluated again in CLN's
// floating point at many more digits (evaluate_precise).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::symbolic {

struct ProbePoint {
    std::map<GiNaC::ex, double, GiNaC::ex_is_less> values;  // t, q, q_dot, q_ddot, quasi-velocities and their rates, parameters
    std::map<GiNaC::ex, double, GiNaC::ex_is_less> rates;   // d/dt of each: 1 for t, q_dot for q, q_ddot for q_dot
};

// Points with t, q, q_dot, q_ddot drawn from [-1, 1] and parameters from their defaults
// scaled by a factor in [0.8, 1.25] (so a relation that holds only for the defaults is not
// mistaken for an identity); a parameter whose default is 0 gets a value in [0.3, 1.3].
std::vector<ProbePoint> probe_points(const model::Model& model, std::size_t count, std::uint64_t seed = 0x5eed);
// Points at the parameters' defaults exactly (for properties of the user's system).
std::vector<ProbePoint> probe_points_at_defaults(const model::Model& model, std::size_t count,
                                                 std::uint64_t seed = 0x5eed);

// The value; NaN if it does not evaluate to a real number there.
double evaluate(const GiNaC::ex& e, const ProbePoint& at);
// The total time derivative along the motion through the point (q̈ taken from the point).
double evaluate_rate(const GiNaC::ex& e, const ProbePoint& at);

// The digits of the precise evaluation: enough that the rounding of an identity's residual
// (about 10^-(digits-3) of its largest terms) lies far below any perturbation an orbit or a
// carrier can carry (a third body's tidal term is 1e-13 of μ/r, and cancelling J2 torques
// reach 1e10 at the probe points: 1e-23 of the terms).
inline constexpr int precise_digits = 50;

// A point's values (or rates) as CLN floats of precise_digits digits, each the double's exact value.
GiNaC::exmap precise_values(const std::map<GiNaC::ex, double, GiNaC::ex_is_less>& values);
// The value at precise_digits digits; nullopt if it does not evaluate to a real number there.
std::optional<GiNaC::numeric> evaluate_precise(const GiNaC::ex& e, const GiNaC::exmap& values);

// Precise evaluation of many expressions at one point, each shared node once across all of them
// (GiNaC's subs + evalf walks the tree, so a subexpression shared k times costs k evaluations,
// and an identity's residual over n equations shares most of its nodes).
class PreciseEvaluator {
public:
    explicit PreciseEvaluator(GiNaC::exmap values) : values_(std::move(values)) {}

    // As evaluate_precise.
    std::optional<GiNaC::numeric> value(const GiNaC::ex& e);
    // ∂e/∂x at the point for each x in `variables` (symbols), by one reverse sweep over e's DAG
    // (reverse-mode differentiation, Griewank & Walther, Evaluating Derivatives, 2008, §3.2);
    // nullopt where e does not evaluate to a real number or holds a node whose partials are not
    // known here (then differentiate symbolically).
    std::optional<std::vector<GiNaC::numeric>> gradient(const GiNaC::ex& e, const std::vector<GiNaC::ex>& variables);

private:
    struct Node {
        GiNaC::ex e;
        std::vector<std::size_t> children;  // indices of the operands, in operand order
        GiNaC::numeric value;
        bool real_number = true;  // evaluated to a number (complex values may still cancel)
    };
    std::size_t visit(const GiNaC::ex& e);
    GiNaC::numeric compute(const GiNaC::ex& e, const std::vector<std::size_t>& children, bool& ok);
    bool local_partials(const Node& node, std::vector<GiNaC::numeric>& out);

    GiNaC::exmap values_;
    std::vector<Node> nodes_;  // every child before its parent
    std::unordered_map<GiNaC::ex, std::size_t> index_;
};

}  // namespace eomc::symbolic
