// A running first-order rounding bound of a derived expression evaluated in double, formed node
// by node at a point (the rules: tests/codegen/power_accuracy.cpp), with the value in 40 digits.
// Needs eomc_generator (GiNaC and codegen::multiplied_power).
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <vector>

#include <ginac/ginac.h>

#include "codegen/kernel_ir.hpp"

namespace test_support {

using GiNaC::ex;
using GiNaC::numeric;

inline const numeric u = numeric(2).power(-53);

// A double as the exact rational it is (GiNaC would keep a double float and round every later
// operation to double).
inline numeric exact(double x) {
    int exponent = 0;
    const double mantissa = std::frexp(x, &exponent);
    const long m = static_cast<long>(std::ldexp(mantissa, 53));
    return numeric(m) * numeric(2).power(exponent - 53);
}

struct Bounded {
    numeric value, error;
};

class RoundingBound {
public:
    RoundingBound(GiNaC::exmap inputs, numeric largest_power) : inputs_(std::move(inputs)), P_(largest_power) {}

    Bounded operator()(const ex& e) {
        if (auto it = memo_.find(e); it != memo_.end()) return it->second;
        const Bounded b = evaluate(e);
        memo_.emplace(e, b);
        return b;
    }

private:
    Bounded evaluate(const ex& e) {
        if (GiNaC::is_a<GiNaC::symbol>(e)) {
            const auto it = inputs_.find(e);
            if (it == inputs_.end()) throw std::runtime_error("no value for " + GiNaC::ex_to<GiNaC::symbol>(e).get_name());
            return {GiNaC::ex_to<numeric>(it->second.evalf()), 0};
        }
        if (GiNaC::is_a<numeric>(e)) {
            const numeric c = GiNaC::ex_to<numeric>(e);
            const bool exact_int = c.is_integer() && GiNaC::abs(c) <= numeric(2).power(53);
            return {GiNaC::ex_to<numeric>(c.evalf()), exact_int ? numeric(0) : GiNaC::abs(c) * u};
        }
        if (GiNaC::is_a<GiNaC::constant>(e)) {
            const numeric c = GiNaC::ex_to<numeric>(e.evalf());
            return {c, GiNaC::abs(c) * u};
        }
        std::vector<Bounded> ops;
        for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back((*this)(e.op(i)));
        if (GiNaC::is_a<GiNaC::add>(e)) {
            numeric v = 0, err = 0, magnitude = 0;
            for (const auto& o : ops) v += o.value, err += o.error, magnitude += GiNaC::abs(o.value);
            return {v, err + numeric(long(ops.size()) - 1) * u * magnitude};
        }
        if (GiNaC::is_a<GiNaC::mul>(e)) {
            numeric v = 1, err = 0;
            for (const auto& o : ops) v *= o.value;
            for (std::size_t i = 0; i < ops.size(); ++i) {
                numeric others = 1;
                for (std::size_t j = 0; j < ops.size(); ++j)
                    if (j != i) others *= GiNaC::abs(ops[j].value);
                err += ops[i].error * others;
            }
            return {v, err + numeric(long(ops.size()) - 1) * u * GiNaC::abs(v)};
        }
        if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<numeric>(e.op(1))) {
            const numeric p = GiNaC::ex_to<numeric>(e.op(1));
            const numeric v = GiNaC::ex_to<numeric>(GiNaC::pow(ops[0].value, p).evalf());
            const numeric own = eomc::codegen::multiplied_power(p) ? 2 * P_ + 4 : numeric(2);
            return {v, GiNaC::abs(v) * (GiNaC::abs(p) * ops[0].error / GiNaC::abs(ops[0].value) + own * u)};
        }
        if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1) {
            const GiNaC::symbol z("z");
            const ex f = GiNaC::ex_to<GiNaC::function>(e).thiscontainer(GiNaC::exvector{z});
            const numeric v = GiNaC::ex_to<numeric>(f.subs(z == ops[0].value).evalf());
            const numeric slope = GiNaC::ex_to<numeric>(f.diff(z).subs(z == ops[0].value).evalf());
            return {v, GiNaC::abs(slope) * ops[0].error + 2 * u * GiNaC::abs(v)};
        }
        throw std::runtime_error("no rounding rule for this node");
    }

    GiNaC::exmap inputs_;
    numeric P_;
    std::map<ex, Bounded, GiNaC::ex_is_less> memo_;
};

// The largest |p| of a numeric power in the expressions.
inline numeric largest_power(const std::vector<ex>& expressions) {
    numeric largest = 0;
    std::function<void(const ex&)> walk = [&](const ex& e) {
        if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<numeric>(e.op(1)))
            if (GiNaC::abs(GiNaC::ex_to<numeric>(e.op(1))) > largest) largest = GiNaC::abs(GiNaC::ex_to<numeric>(e.op(1)));
        for (std::size_t i = 0; i < e.nops(); ++i) walk(e.op(i));
    };
    for (const ex& e : expressions) walk(e);
    return largest;
}

}  // namespace test_support
