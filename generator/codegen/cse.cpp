// Common-subexpression elimination. GiNaC has none, so: count how often every compound
// node occurs across all outputs of a function (descending into a node only the first
// time it is seen, so a shared subtree is counted once per parent), then rebuild the
// outputs bottom-up, turning every node used more than once into a temporary.
//
// Three refinements matter for mechanics: a product's numeric coefficient is split off, so
// −m·l·cos q and 2·m·l·cos q share m·l·cos q; the base of a power the printer multiplies out is
// always a temporary, because x^3 is emitted as x*x*x; and the half-integer powers of one base
// share one sqrt and one division (r⁻³, r⁻⁵ and r⁻⁷ of gravity with J2: HalfPowers below).
#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "codegen/canonical_order.hpp"
#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "symbolic/exact_constants.hpp"

namespace eomc::codegen {

using GiNaC::ex;

namespace {

bool is_leaf(const ex& e) {
    return GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e);
}

// x^k printed with multiplications and sqrt (multiplied_power), so that x appears in the text more
// than once when |k| > 1.
bool is_multiplied_power(const ex& e) {
    return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
           multiplied_power(GiNaC::ex_to<GiNaC::numeric>(e.op(1)));
}

// j of a half-integer exponent j/2 that the printer multiplies out, else 0.
long half_power_numerator(const ex& e) {
    if (!is_multiplied_power(e)) return 0;
    const GiNaC::numeric k = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
    return k.is_integer() ? 0 : (2 * k).to_long();
}

// A product c·x·y·… with a numeric c ≠ 1 and at least two other factors, split as (c, x·y·…).
bool split_coefficient(const ex& e, ex& coefficient, ex& rest) {
    if (!GiNaC::is_a<GiNaC::mul>(e)) return false;
    GiNaC::exvector factors;
    coefficient = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) {
        if (GiNaC::is_a<GiNaC::numeric>(e.op(i))) coefficient *= e.op(i);
        else factors.push_back(e.op(i));
    }
    if (coefficient.is_equal(1) || factors.size() < 2) return false;
    rest = GiNaC::mul(factors);
    return true;
}

class Eliminator {
public:
    Eliminator(const std::string& prefix) : prefix_(prefix) {}

    // A symbol standing for `value` (HalfPowers' sqrt and reciprocal): counted where it is used,
    // and emitted as a temporary before its first use when used twice or more, else inlined.
    void defer(const ex& placeholder, const ex& value) { deferred_.emplace(placeholder, value); }

    void count(const ex& e) {
        if (auto it = deferred_.find(e); it != deferred_.end()) {
            if (++uses_[e] == 1) count(it->second);
            return;
        }
        if (is_leaf(e)) return;
        ex c, rest;
        if (split_coefficient(e, c, rest)) return count(rest);
        if (++uses_[e] > 1) return;
        for (const ex& op : order_.operands(e)) count(op);
        if (is_multiplied_power(e) && !is_leaf(e.op(0)) && GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(e.op(1))) > 1)
            ++uses_[e.op(0)];
    }

    ex rewrite(const ex& e) {
        if (auto it = deferred_.find(e); it != deferred_.end()) {
            if (auto done = temporary_of_.find(e); done != temporary_of_.end()) return done->second;
            const ex rebuilt = rewrite(it->second);
            if (uses_[e] < 2) return rebuilt;
            GiNaC::symbol w(prefix_ + std::to_string(block_.temporaries.size()));
            block_.temporaries.push_back({w, rebuilt});
            temporary_of_.emplace(e, w);
            return w;
        }
        if (is_leaf(e)) return e;
        ex c, rest;
        if (split_coefficient(e, c, rest)) return c * rewrite(rest);
        if (auto it = temporary_of_.find(e); it != temporary_of_.end()) return it->second;

        ex rebuilt;
        const auto ops = order_.operands(e);
        if (GiNaC::is_a<GiNaC::add>(e)) {
            GiNaC::exvector terms;
            for (const ex& op : ops) terms.push_back(rewrite(op));
            rebuilt = GiNaC::add(terms);
        } else if (GiNaC::is_a<GiNaC::mul>(e)) {
            GiNaC::exvector factors;
            for (const ex& op : ops) factors.push_back(rewrite(op));
            rebuilt = GiNaC::mul(factors);
        } else if (GiNaC::is_a<GiNaC::power>(e)) {
            rebuilt = GiNaC::pow(rewrite(e.op(0)), e.op(1));
        } else {
            GiNaC::exvector args;
            for (const ex& op : ops) args.push_back(rewrite(op));
            rebuilt = GiNaC::ex_to<GiNaC::function>(e).thiscontainer(args);
        }
        if (uses_[e] > 1 && count_operations(rebuilt) > 0) {
            GiNaC::symbol w(prefix_ + std::to_string(block_.temporaries.size()));
            block_.temporaries.push_back({w, rebuilt});
            temporary_of_.emplace(e, w);
            return w;
        }
        return rebuilt;
    }

    Block& block() { return block_; }

private:
    std::string prefix_;
    CanonicalOrder order_;
    std::map<ex, std::size_t, GiNaC::ex_is_less> uses_;
    std::map<ex, ex, GiNaC::ex_is_less> temporary_of_;
    std::map<ex, ex, GiNaC::ex_is_less> deferred_;
    Block block_;
};

// The half-integer powers b^(j/2) of a base that occurs with two or more such exponents, rewritten
// over s = sqrt(b) and d = 1/(b^((J−1)/2)·s) = b^(−J/2), J the largest |j| of a negative exponent:
//   b^(j/2), j > 0:   b^((j−1)/2)·s
//   b^(−k/2):         d·b^((J−k)/2)
// so that gravity's r⁻³, r⁻⁵, r⁻⁷ (b = r²) cost one sqrt, one division and a few multiplications
// instead of a pow() each. s and d are placeholders the Eliminator emits as temporaries. A base
// with one exponent only is left to the printer, which writes the same operations inline.
class HalfPowers {
public:
    explicit HalfPowers(Eliminator& eliminator) : eliminator_(eliminator) {}

    void collect(const ex& e) {
        if (is_leaf(e) || !seen_.insert(e).second) return;
        if (const long j = half_power_numerator(e)) {
            auto [it, fresh] = exponents_.try_emplace(e.op(0));
            if (fresh) bases_.push_back(e.op(0));
            it->second.insert(j);
            return;  // a half power inside b is left to the printer
        }
        for (const ex& op : order_.operands(e)) collect(op);
    }

    // Placeholders for the bases with two or more exponents, in the order they were first met.
    void define() {
        for (const ex& b : bases_) {
            const std::set<long>& js = exponents_.at(b);
            if (js.size() < 2) continue;
            const std::string n = std::to_string(forms_.size());
            Form form{GiNaC::symbol("eomc_half_power_sqrt_" + n), GiNaC::symbol("eomc_half_power_inverse_" + n), 0};
            eliminator_.defer(form.s, GiNaC::sqrt(b));
            for (long j : js) form.largest = std::max(form.largest, -j);
            if (form.largest > 0) eliminator_.defer(form.d, GiNaC::pow(GiNaC::pow(b, (form.largest - 1) / 2) * form.s, -1));
            forms_.emplace(b, form);
        }
    }

    ex rewrite(const ex& e) {
        if (is_leaf(e) || forms_.empty()) return e;
        if (auto it = done_.find(e); it != done_.end()) return it->second;
        ex out;
        const long j = half_power_numerator(e);
        if (auto form = j ? forms_.find(e.op(0)) : forms_.end(); form != forms_.end()) {
            const Form& f = form->second;
            out = j > 0 ? GiNaC::pow(e.op(0), (j - 1) / 2) * f.s : f.d * GiNaC::pow(e.op(0), (f.largest + j) / 2);
        } else {
            GiNaC::exvector ops;
            for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back(rewrite(e.op(i)));
            out = rebuild(e, ops);
        }
        done_.emplace(e, out);
        return out;
    }

private:
    struct Form {
        GiNaC::symbol s, d;
        long largest;  // J: the largest |j| of a negative exponent (0: none)
    };
    static ex rebuild(const ex& e, const GiNaC::exvector& ops) {
        if (GiNaC::is_a<GiNaC::add>(e)) return GiNaC::add(ops);
        if (GiNaC::is_a<GiNaC::mul>(e)) return GiNaC::mul(ops);
        if (GiNaC::is_a<GiNaC::power>(e)) return GiNaC::pow(ops[0], ops[1]);
        return GiNaC::ex_to<GiNaC::function>(e).thiscontainer(ops);
    }

    Eliminator& eliminator_;
    CanonicalOrder order_;
    std::set<ex, GiNaC::ex_is_less> seen_;
    std::vector<ex> bases_;
    std::map<ex, std::set<long>, GiNaC::ex_is_less> exponents_;
    std::map<ex, Form, GiNaC::ex_is_less> forms_;
    std::map<ex, ex, GiNaC::ex_is_less> done_;
};

}  // namespace

namespace {

// Memoized by structure: GiNaC shares subtrees, so a derived expression can be a DAG whose
// tree size is far larger than its node count.
using OperationMemo = std::unordered_map<ex, std::size_t>;

std::size_t tree_operations(const ex& e, OperationMemo& memo) {
    if (is_leaf(e)) return 0;
    if (auto it = memo.find(e); it != memo.end()) return it->second;
    std::size_t ops = 0;
    for (std::size_t i = 0; i < e.nops(); ++i) ops += tree_operations(e.op(i), memo);
    if (GiNaC::is_a<GiNaC::add>(e)) {
        ops += e.nops() - 1;
    } else if (GiNaC::is_a<GiNaC::mul>(e)) {
        std::size_t factors = e.nops();
        // A coefficient of −1 is a sign, absorbed by the subtraction it ends up in.
        for (std::size_t i = 0; i < e.nops(); ++i)
            if (e.op(i).is_equal(-1)) --factors;
        ops += factors > 0 ? factors - 1 : 0;
    } else if (is_multiplied_power(e)) {
        const GiNaC::numeric k = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
        const bool half = !k.is_integer();
        const long m = (GiNaC::abs(k) - (half ? GiNaC::numeric(1, 2) : GiNaC::numeric(0))).to_long();
        // x^m's multiplications, then sqrt and the product with it, then 1/(…).
        ops += (m > 0 ? powering_multiplications(std::size_t(m)) : 0) + (half ? (m > 0 ? 2 : 1) : 0) + (k.is_negative() ? 1 : 0);
    } else {
        ops += 1;  // sqrt, pow, a function call
    }
    memo.emplace(e, ops);
    return ops;
}

}  // namespace

std::size_t count_operations(const ex& e) {
    OperationMemo memo;
    return tree_operations(e, memo);
}

bool multiplied_power(const GiNaC::numeric& k) {
    if (GiNaC::abs(k) > max_multiplied_power) return false;
    return k.is_integer() || (2 * k).is_integer();
}

std::size_t powering_multiplications(unsigned long m) {
    std::size_t squarings = 0, bits = 0;
    for (unsigned long r = m; r > 1; r /= 2) ++squarings;
    for (unsigned long r = m; r > 0; r /= 2) bits += r % 2;
    return squarings + bits - 1;
}

Block eliminate_common_subexpressions(const std::vector<ex>& outputs, const std::string& temp_prefix) {
    Eliminator eliminator(temp_prefix);
    std::size_t before = 0;
    std::vector<ex> canonical;
    for (const ex& e : outputs) {
        try {
            canonical.push_back(canonical_form(symbolic::fold_ill_conditioned_constants(e)));
        } catch (const symbolic::ConstantOutOfReach& reach) {
            throw EmitError(reach.what());
        }
    }
    HalfPowers half_powers(eliminator);
    for (const ex& e : canonical) {
        before += count_operations(e);
        half_powers.collect(e);
    }
    half_powers.define();
    std::vector<ex> shared;
    for (const ex& e : canonical) {
        shared.push_back(half_powers.rewrite(e));
        eliminator.count(shared.back());
    }
    Block& block = eliminator.block();
    for (const ex& e : shared) block.outputs.push_back(eliminator.rewrite(e));
    block.ops_before = before;
    block.ops_after = 0;
    for (const auto& t : block.temporaries) block.ops_after += count_operations(t.value);
    for (const ex& e : block.outputs) block.ops_after += count_operations(e);
    return std::move(block);
}

}  // namespace eomc::codegen
