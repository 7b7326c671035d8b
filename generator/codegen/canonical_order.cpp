#include "codegen/canonical_order.hpp"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <sstream>
#include <string>

namespace eomc::codegen {

namespace {

std::uint64_t fnv1a(const std::string& s, std::uint64_t h = 0xcbf29ce484222325ull) {
    for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    return h * 0xff51afd7ed558ccdull;
}

bool is_power_of_symbol(const GiNaC::ex& e) {
    return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::symbol>(e.op(0)) && GiNaC::is_a<GiNaC::numeric>(e.op(1));
}

// Numbers, then symbols, then powers of symbols (x^2, 1/y), then everything else.
int rank(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return 0;
    if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 1;
    if (is_power_of_symbol(e)) return 2;
    return 3;
}

std::string printed(const GiNaC::ex& e) {
    std::ostringstream os;
    os << e;
    return os.str();
}

std::string name(const GiNaC::ex& e) {
    return GiNaC::is_a<GiNaC::symbol>(e) ? GiNaC::ex_to<GiNaC::symbol>(e).get_name() : std::string("Pi");
}

}  // namespace

std::uint64_t CanonicalOrder::key(const GiNaC::ex& e) {
    if (auto it = keys_.find(e); it != keys_.end()) return it->second;
    std::uint64_t h;
    if (rank(e) < 2) {  // leaves
        h = fnv1a(rank(e) == 1 ? name(e) : printed(e), std::uint64_t(rank(e)));
    } else {
        std::string tag = GiNaC::is_a<GiNaC::add>(e)     ? "+"
                          : GiNaC::is_a<GiNaC::mul>(e)   ? "*"
                          : GiNaC::is_a<GiNaC::power>(e) ? "^"
                          : GiNaC::is_a<GiNaC::function>(e) ? GiNaC::ex_to<GiNaC::function>(e).get_name()
                                                            : GiNaC::ex_to<GiNaC::basic>(e).class_name();
        h = fnv1a(tag);
        std::vector<std::uint64_t> parts;
        for (std::size_t i = 0; i < e.nops(); ++i) parts.push_back(key(e.op(i)));
        // Sums and products are commutative: their key must not depend on operand order.
        if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) std::sort(parts.begin(), parts.end());
        for (std::uint64_t p : parts) h = mix(h, p);
    }
    keys_.emplace(e, h);
    return h;
}

bool CanonicalOrder::less(const GiNaC::ex& a, const GiNaC::ex& b) {
    const int ra = rank(a), rb = rank(b);
    if (ra != rb) return ra < rb;
    if (ra == 1) return name(a) < name(b);
    if (ra == 2) {
        if (name(a.op(0)) != name(b.op(0))) return name(a.op(0)) < name(b.op(0));
        return GiNaC::ex_to<GiNaC::numeric>(a.op(1)) < GiNaC::ex_to<GiNaC::numeric>(b.op(1));
    }
    if (ra == 0) {
        const GiNaC::numeric& x = GiNaC::ex_to<GiNaC::numeric>(a);
        const GiNaC::numeric& y = GiNaC::ex_to<GiNaC::numeric>(b);
        if (x.is_real() && y.is_real()) return x < y;
        return printed(a) < printed(b);
    }
    return key(a) < key(b);
}

std::vector<GiNaC::ex> CanonicalOrder::operands(const GiNaC::ex& e) {
    std::vector<GiNaC::ex> ops;
    for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back(e.op(i));
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e))
        std::stable_sort(ops.begin(), ops.end(), [this](const GiNaC::ex& a, const GiNaC::ex& b) { return less(a, b); });
    return ops;
}

}  // namespace eomc::codegen

namespace eomc::codegen {

namespace {

class Canonicalizer {
public:
    GiNaC::ex operator()(const GiNaC::ex& e) {
        if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return e;
        if (auto it = memo_.find(e); it != memo_.end()) return it->second;
        const GiNaC::ex result = rebuild(e);
        memo_.emplace(e, result);
        return result;
    }

private:
    // Of a sum S and its negation −S, the one with the smaller structural key is the
    // canonical representative: true when that is −S.
    bool prefer_negated(const GiNaC::ex& sum, GiNaC::ex& negated) {
        GiNaC::exvector terms;
        for (std::size_t i = 0; i < sum.nops(); ++i) terms.push_back(-sum.op(i));
        negated = GiNaC::add(terms);
        return order_.key(negated) < order_.key(sum);
    }

    // A term as base → integer exponent (numeric coefficients left out).
    static std::map<GiNaC::ex, GiNaC::numeric, GiNaC::ex_is_less> factors_of(const GiNaC::ex& term) {
        std::map<GiNaC::ex, GiNaC::numeric, GiNaC::ex_is_less> out;
        auto add_factor = [&out](const GiNaC::ex& f) {
            if (GiNaC::is_a<GiNaC::numeric>(f)) return;
            if (GiNaC::is_a<GiNaC::power>(f) && f.op(1).info(GiNaC::info_flags::integer))
                out[f.op(0)] += GiNaC::ex_to<GiNaC::numeric>(f.op(1));
            else
                out[f] += 1;
        };
        if (GiNaC::is_a<GiNaC::mul>(term))
            for (std::size_t i = 0; i < term.nops(); ++i) add_factor(term.op(i));
        else
            add_factor(term);
        return out;
    }

    // x·a + x²·b → x·(a + x·b): the factors (with the smallest positive power) that every
    // term has. Structural matching only; no polynomial gcd (that is what makes GiNaC's
    // collect_common_factors too slow for large equations).
    GiNaC::ex factor_out_common(const GiNaC::ex& sum) {
        if (!GiNaC::is_a<GiNaC::add>(sum)) return sum;
        auto common = factors_of(sum.op(0));
        for (std::size_t i = 1; i < sum.nops() && !common.empty(); ++i) {
            const auto f = factors_of(sum.op(i));
            for (auto it = common.begin(); it != common.end();) {
                auto found = f.find(it->first);
                if (found == f.end() || !found->second.is_positive() || !it->second.is_positive()) {
                    it = common.erase(it);
                } else {
                    if (found->second < it->second) it->second = found->second;
                    ++it;
                }
            }
        }
        if (common.empty()) return sum;
        GiNaC::ex divisor = 1;
        for (const auto& [base, k] : common) divisor *= GiNaC::pow(base, k);
        GiNaC::exvector rest;
        for (std::size_t i = 0; i < sum.nops(); ++i) rest.push_back(sum.op(i) / divisor);
        return divisor * factor_out_common(GiNaC::add(rest));
    }

    GiNaC::ex rebuild(const GiNaC::ex& e) {
        GiNaC::exvector ops;
        for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back((*this)(e.op(i)));
        if (GiNaC::is_a<GiNaC::add>(e)) return factor_out_common(GiNaC::add(ops));
        if (GiNaC::is_a<GiNaC::mul>(e)) {
            GiNaC::numeric sign = 1;
            for (auto& factor : ops) {
                const bool is_sum = GiNaC::is_a<GiNaC::add>(factor);
                const bool is_sum_power = GiNaC::is_a<GiNaC::power>(factor) && GiNaC::is_a<GiNaC::add>(factor.op(0)) &&
                                          factor.op(1).info(GiNaC::info_flags::integer);
                if (!is_sum && !is_sum_power) continue;
                GiNaC::ex flipped;
                if (!prefer_negated(is_sum ? factor : factor.op(0), flipped)) continue;
                if (is_sum) {
                    factor = flipped;
                    sign = -sign;
                } else {
                    factor = GiNaC::pow(flipped, factor.op(1));
                    if (GiNaC::ex_to<GiNaC::numeric>(factor.op(1)).is_odd()) sign = -sign;
                }
            }
            return sign * GiNaC::mul(ops);
        }
        if (GiNaC::is_a<GiNaC::power>(e)) {
            GiNaC::ex flipped;
            if (GiNaC::is_a<GiNaC::add>(ops[0]) && ops[1].info(GiNaC::info_flags::integer) &&
                prefer_negated(ops[0], flipped))
                return (GiNaC::ex_to<GiNaC::numeric>(ops[1]).is_odd() ? -1 : 1) * GiNaC::pow(flipped, ops[1]);
            return GiNaC::pow(ops[0], ops[1]);
        }
        if (GiNaC::is_a<GiNaC::function>(e)) return GiNaC::ex_to<GiNaC::function>(e).thiscontainer(ops);
        return e;
    }

    CanonicalOrder order_;
    std::unordered_map<GiNaC::ex, GiNaC::ex> memo_;
};

}  // namespace

GiNaC::ex canonical_form(const GiNaC::ex& e) { return Canonicalizer()(e); }

}  // namespace eomc::codegen
