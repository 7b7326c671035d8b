// A straight-line function emitted in parts past operations_per_part (kernel_parts.hpp's
// split_function): the Jacobian's large blocks.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

using GiNaC::ex;

namespace {

// A straight-line function past this many operations is emitted in parts, each with only the
// temporaries its outputs need. g++'s register allocation grows faster than linearly with one
// function's size: the 12-link 3-D chain's Jacobian terms (30k operations, 1394 temporaries) took
// 19 s CPU at -O2 as one function. The parts recompute the temporaries they share; the Jacobian,
// the one place this applies, is called once per implicit step (bench/RESULTS.md).
constexpr std::size_t operations_per_part = 4000;

// The outputs [first, last) of `block` with the temporaries they reach.
Block part_of(const Block& block, std::size_t first, std::size_t last) {
    Block part;
    part.outputs.assign(block.outputs.begin() + std::ptrdiff_t(first), block.outputs.begin() + std::ptrdiff_t(last));
    std::set<ex, GiNaC::ex_is_less> needed;
    for (const ex& o : part.outputs) collect_symbols(o, needed);
    for (auto it = block.temporaries.rbegin(); it != block.temporaries.rend(); ++it) {
        if (!needed.count(it->symbol)) continue;
        collect_symbols(it->value, needed);
        part.temporaries.push_back(*it);
    }
    std::reverse(part.temporaries.begin(), part.temporaries.end());
    return part;
}

}  // namespace

SplitBody split_function(const KernelIR& ir, const LocalNames& names, const Block& block,
                         const std::vector<std::string>& targets, Inputs inputs, const std::string& name,
                         const std::string& parameters, const std::string& arguments,
                         const std::vector<std::string>& arrays) {
    const std::size_t count = (block.ops_after + operations_per_part - 1) / operations_per_part;
    if (count < 2 || block.outputs.size() < 2) return {function_body(ir, names, block, targets, inputs), ""};
    SplitBody split;
    const std::size_t n = block.outputs.size(), parts = std::min(count, n);
    for (std::size_t k = 0; k < parts; ++k) {
        const std::size_t first = k * n / parts, last = (k + 1) * n / parts;
        std::string unused;
        for (const auto& array : arrays)
            if (std::none_of(targets.begin() + std::ptrdiff_t(first), targets.begin() + std::ptrdiff_t(last),
                             [&](const std::string& target) { return target.rfind(array + "[", 0) == 0; }))
                unused += "(void)" + array + ";\n";
        const std::vector<std::string> part_targets(targets.begin() + std::ptrdiff_t(first),
                                                    targets.begin() + std::ptrdiff_t(last));
        split.parts += fmt::format(
            "\n    // Outputs {} to {} of {}.\n"
            "    template <class S>\n"
            "    static void {}part{}_({}) {{\n{}\n    }}\n",
            first, last - 1, name, name, k, parameters,
            indent(unused + function_body(ir, names, part_of(block, first, last), part_targets, inputs), 8));
        split.body += fmt::format("{}part{}_({});\n", name, k, arguments);
    }
    split.body = fmt::format("// {} operations after CSE: in {} parts (operations_per_part).\n", block.ops_after, parts) +
                 split.body;
    split.body.pop_back();
    return split;
}

}  // namespace eomc::codegen
