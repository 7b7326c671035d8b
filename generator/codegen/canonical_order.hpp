// A deterministic order for the operands of sums and products.
//
// GiNaC orders operands by hash values derived from each symbol's creation serial, so the
// same scene could print differently in two processes that created symbols in another
// order. Generated code must be byte-identical, so everything the code generator walks
// or prints is ordered here instead: numbers first, then symbols by name, then compound
// expressions by a structural hash that depends only on names and numbers.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::codegen {

class CanonicalOrder {
public:
    // The operands of e, ordered canonically (numbers first, then symbols by name).
    std::vector<GiNaC::ex> operands(const GiNaC::ex& e);
    std::uint64_t key(const GiNaC::ex& e);
    bool less(const GiNaC::ex& a, const GiNaC::ex& b);

private:
    std::map<GiNaC::ex, std::uint64_t, GiNaC::ex_is_less> keys_;
};

// The same expression, rebuilt bottom-up so that equal subtrees become identical:
// - factors common to every term of a sum are taken out (m2·w + m3·w → w·(m2 + m3)):
//   GiNaC keeps sums distributed, and a factor repeated across terms is work that
//   common-subexpression elimination cannot see;
// - every sum that is a factor of a product (or the base of an integer power) is signed
//   canonically: c·(−a + b)·x and −c·(a − b)·x are the same value, and which of the two
//   GiNaC builds depends on its term order.
GiNaC::ex canonical_form(const GiNaC::ex& e);

}  // namespace eomc::codegen
