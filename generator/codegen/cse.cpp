// Common-subexpression elimination. GiNaC has none, so: count how often every compound
// node occurs across all outputs of a function (descending into a node only the first
// time it is seen, so a shared subtree is counted once per parent), then rebuild the
// outputs bottom-up, turning every node used more than once into a temporary.
//
// Two refinements matter for mechanics: a product's numeric coefficient is split off, so
// −m·l·cos q and 2·m·l·cos q share m·l·cos q; and the base of an integer power is always
// a temporary, because x^3 is emitted as x*x*x.
#include <map>
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

bool is_integer_power(const ex& e) {
    return GiNaC::is_a<GiNaC::power>(e) && e.op(1).info(GiNaC::info_flags::integer);
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

    void count(const ex& e) {
        if (is_leaf(e)) return;
        ex c, rest;
        if (split_coefficient(e, c, rest)) return count(rest);
        if (++uses_[e] > 1) return;
        for (const ex& op : order_.operands(e)) count(op);
        if (is_integer_power(e) && !is_leaf(e.op(0)) && GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(e.op(1))) > 1)
            ++uses_[e.op(0)];
    }

    ex rewrite(const ex& e) {
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
    Block block_;
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
    } else if (is_integer_power(e)) {
        const long k = GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_long();
        const std::size_t m = std::size_t(k < 0 ? -k : k);
        ops += (m > 0 ? m - 1 : 0) + (k < 0 ? 1 : 0);
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
    for (const ex& e : canonical) {
        before += count_operations(e);
        eliminator.count(e);
    }
    Block& block = eliminator.block();
    for (const ex& e : canonical) block.outputs.push_back(eliminator.rewrite(e));
    block.ops_before = before;
    block.ops_after = 0;
    for (const auto& t : block.temporaries) block.ops_after += count_operations(t.value);
    for (const ex& e : block.outputs) block.ops_after += count_operations(e);
    return std::move(block);
}

}  // namespace eomc::codegen
