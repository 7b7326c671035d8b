#include "codegen/solve_plan.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <numeric>
#include <set>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"

namespace eomc::codegen {

using GiNaC::ex;

namespace {

bool depends_on(const ex& e, const std::vector<ex>& symbols) {
    return std::any_of(symbols.begin(), symbols.end(), [&](const ex& s) { return e.has(s); });
}

// The velocities coupled through nonzero entries of M: connected components of its graph,
// each ascending, ordered by their first velocity.
std::vector<std::vector<std::size_t>> coupled_blocks(const GiNaC::matrix& M) {
    const std::size_t n = M.rows();
    std::vector<std::size_t> root(n);
    std::iota(root.begin(), root.end(), 0);
    const auto find = [&](std::size_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (!M(unsigned(i), unsigned(j)).is_zero()) root[find(i)] = find(j);
    std::map<std::size_t, std::vector<std::size_t>> by_root;
    for (std::size_t i = 0; i < n; ++i) by_root[find(i)].push_back(i);
    std::vector<std::vector<std::size_t>> blocks;
    for (auto& [r, members] : by_root) blocks.push_back(std::move(members));
    std::sort(blocks.begin(), blocks.end());
    return blocks;
}

// Straight-line code under construction: the temporaries of a block, extended one value at a time.
class StraightLine {
public:
    StraightLine(Block block, const std::string& prefix) : block_(std::move(block)), prefix_(prefix) {}

    // A number or a symbol as it is; anything else becomes the next temporary.
    ex name(const ex& value) {
        if (GiNaC::is_a<GiNaC::numeric>(value) || GiNaC::is_a<GiNaC::symbol>(value)) return value;
        GiNaC::symbol w(prefix_ + std::to_string(block_.temporaries.size()));
        block_.temporaries.push_back({w, value});
        return w;
    }
    // 1/d, named once per distinct d (equal pivots, a particle's m in several rows, share it).
    ex reciprocal(const ex& d) {
        const ex named = name(d);
        auto [at, fresh] = reciprocals_.try_emplace(named);
        if (fresh) at->second = name(GiNaC::pow(named, -1));
        return at->second;
    }
    std::size_t size() const { return block_.temporaries.size(); }
    Block& block() { return block_; }

private:
    Block block_;
    std::string prefix_;
    std::map<ex, ex, GiNaC::ex_is_less> reciprocals_;
};

void collect_symbols(const ex& e, std::set<ex, GiNaC::ex_is_less>& out) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        out.insert(e);
        return;
    }
    for (std::size_t i = 0; i < e.nops(); ++i) collect_symbols(e.op(i), out);
}

// Drops the temporaries no output reaches (M's, when the solve needs none of M: identity), which
// would otherwise be unused variables in the emitted code.
void prune(Block& block) {
    std::set<ex, GiNaC::ex_is_less> needed;
    for (const ex& o : block.outputs) collect_symbols(o, needed);
    std::vector<Temporary> kept;
    for (auto it = block.temporaries.rbegin(); it != block.temporaries.rend(); ++it) {
        if (!needed.count(it->symbol)) continue;
        collect_symbols(it->value, needed);
        kept.push_back(*it);
    }
    block.temporaries.assign(kept.rbegin(), kept.rend());
}

// X = A⁻¹B for one block A = M[idx, idx] of size s ≥ 2, by A = L D Lᵀ (L unit lower triangular):
// with E_ij = L_ij d_j, for j = 0 … s−1
//     d_j  = a_jj − Σ_{k<j} E_jk L_jk,    E_ij = a_ij − Σ_{k<j} E_ik L_jk,    L_ij = E_ij / d_j  (i > j),
// then L y = b, z = D⁻¹ y, Lᵀ x = z per column (Golub, Van Loan, Matrix Computations, 4th ed.,
// Alg. 4.1.2, with the products E = L D kept so that each multiplies once). Without pivoting: A is
// positive definite, so every d_j > 0 and the factorization is backward stable (Higham, Accuracy
// and Stability of Numerical Algorithms, 2nd ed., Thm. 10.3 for Cholesky; LDLᵀ is the same
// arithmetic with the square roots moved into D). A zero d_j at run time (M singular) divides by
// zero: the rates become inf or NaN, which the runtime's checker stops on, never a finite guess.
void solve_dense(StraightLine& code, const std::vector<std::size_t>& idx, const std::vector<std::vector<ex>>& a,
                 const std::vector<std::vector<ex>>& b, std::vector<std::vector<ex>>& x) {
    const std::size_t s = idx.size(), columns = b.empty() ? 0 : b[0].size();
    std::vector<std::vector<ex>> E(s, std::vector<ex>(s, 0)), L(s, std::vector<ex>(s, 0));
    std::vector<ex> inverse_d(s);
    for (std::size_t j = 0; j < s; ++j) {
        ex d = a[j][j];
        for (std::size_t k = 0; k < j; ++k) d -= E[j][k] * L[j][k];
        if (d.is_zero())
            throw EmitError(fmt::format("the mass matrix has a zero pivot at velocity {} (it is singular, or indefinite "
                                        "so that LDLᵀ needs pivoting): M must be positive definite",
                                        idx[j]));
        inverse_d[j] = code.reciprocal(d);
        for (std::size_t i = j + 1; i < s; ++i) {
            ex e = a[i][j];
            for (std::size_t k = 0; k < j; ++k) e -= E[i][k] * L[j][k];
            E[i][j] = code.name(e);
            L[i][j] = code.name(E[i][j] * inverse_d[j]);
        }
    }
    for (std::size_t c = 0; c < columns; ++c) {
        std::vector<ex> y(s);
        for (std::size_t i = 0; i < s; ++i) {
            ex v = b[i][c];
            for (std::size_t k = 0; k < i; ++k) v -= L[i][k] * y[k];
            y[i] = code.name(v);
        }
        for (std::size_t i = s; i-- > 0;) {
            ex v = y[i] * inverse_d[i];
            for (std::size_t k = i + 1; k < s; ++k) v -= L[k][i] * x[idx[k]][c];
            x[idx[i]][c] = i > 0 ? code.name(v) : v;  // x of the block's first velocity is read by no other
        }
    }
}

// The saddle-point matrix K = [[M, Wᵀ], [W, 0]] of (M, W), W m × n row-major.
GiNaC::matrix saddle_point_matrix(const GiNaC::matrix& M, const std::vector<ex>& W, std::size_t m) {
    const std::size_t n = M.rows();
    GiNaC::matrix K{unsigned(n + m), unsigned(n + m)};
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) K(unsigned(i), unsigned(j)) = M(unsigned(i), unsigned(j));
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t k = 0; k < n; ++k) K(unsigned(n + a), unsigned(k)) = K(unsigned(k), unsigned(n + a)) = W[a * n + k];
    return K;
}

// X = K⁻¹B in straight-line code for the saddle-point K of plan_saddle_point: `lower(i, j)` gives
// K's entries for j ≤ i, `b` is (n + m) × columns; both are named first, so that their operations
// stay the system's (`first` is where the solve's own temporaries begin). Returns X and, in
// `named`, K's lower triangle as the code names it.
std::vector<std::vector<ex>> solve_saddle(StraightLine& code, const SolvePlan& plan, std::size_t size,
                                          const std::function<ex(std::size_t, std::size_t)>& lower,
                                          const std::vector<std::vector<ex>>& b_raw,
                                          std::vector<std::vector<ex>>& named, std::size_t& first) {
    const std::size_t columns = b_raw.empty() ? 0 : b_raw[0].size();
    std::vector<std::vector<ex>> b(size, std::vector<ex>(columns)), x(size, std::vector<ex>(columns));
    named.assign(size, std::vector<ex>(size, 0));
    for (std::size_t i = 0; i < size; ++i)
        for (std::size_t c = 0; c < columns; ++c) b[i][c] = code.name(b_raw[i][c]);
    for (const auto& block : plan.blocks)
        for (std::size_t r = 0; r < block.size(); ++r)
            for (std::size_t s = 0; s <= r; ++s) named[block[r]][block[s]] = code.name(lower(block[r], block[s]));
    first = code.size();
    for (const auto& block : plan.blocks) {
        if (block.size() == 1) {  // a velocity no row touches, with no coupling in M
            const std::size_t i = block[0];
            const ex inverse = GiNaC::pow(named[i][i], -1);
            for (std::size_t c = 0; c < columns; ++c) x[i][c] = b[i][c] * inverse;
            continue;
        }
        std::vector<std::vector<ex>> ab(block.size(), std::vector<ex>(block.size())), bb;
        for (std::size_t r = 0; r < block.size(); ++r) {
            for (std::size_t s = 0; s <= r; ++s) ab[r][s] = named[block[r]][block[s]];
            bb.push_back(b[block[r]]);
        }
        try {
            solve_dense(code, block, ab, bb, x);
        } catch (const EmitError&) {  // a pivot that is 0 as written: known at generation time
            throw EmitError("the constraint rows are dependent (W has no full row rank), or M is singular: "
                            "M u̇ − Wᵀλ = f, W u̇ = r has no unique solution");
        }
    }
    return x;
}

// K's lower triangle from a system's outputs: M (n², row-major) first, W (m × n) from `w_at` on.
std::function<ex(std::size_t, std::size_t)> saddle_lower(const Block& system, std::size_t n, std::size_t w_at) {
    return [&system, n, w_at](std::size_t i, std::size_t j) -> ex {
        if (i < n) return system.outputs[i * n + j];
        if (j < n) return system.outputs[w_at + (i - n) * n + j];
        return 0;
    };
}

// A straight-line solve's operation counts: as derived (the system's, then `solve_ops` of the
// solve's own), and what is left after pruning.
void count_outputs(Block& out, std::size_t system_ops, std::size_t solve_ops) {
    prune(out);
    out.ops_before = system_ops + solve_ops;
    out.ops_after = 0;
    for (const auto& t : out.temporaries) out.ops_after += count_operations(t.value);
    for (const ex& e : out.outputs) out.ops_after += count_operations(e);
}

// The same where the solve's own operations are its temporaries from `first` on and its outputs.
void count_solve(Block& result, std::size_t system_ops, std::size_t first) {
    std::size_t solve_ops = 0;
    for (std::size_t k = first; k < result.temporaries.size(); ++k) solve_ops += count_operations(result.temporaries[k].value);
    for (const ex& e : result.outputs) solve_ops += count_operations(e);
    count_outputs(result, system_ops, solve_ops);
}

}  // namespace

SolvePlan plan_solve(const GiNaC::matrix& M, const std::vector<ex>& varying) {
    const std::size_t n = M.rows();
    SolvePlan plan;
    if (n == 0) return plan;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < i; ++j) {
            const ex& lower = M(unsigned(i), unsigned(j));
            const ex& upper = M(unsigned(j), unsigned(i));
            if (!lower.is_equal(upper) && !(lower - upper).expand().is_zero())
                throw EmitError(fmt::format("the mass matrix is not symmetric (entries ({0}, {1}) and ({1}, {0}) differ): "
                                            "M u̇ = f needs the symmetric M of a kinetic energy",
                                            i, j));
        }
    plan.constant = true;
    plan.numeric = true;
    bool identity = true;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            const ex& e = M(unsigned(i), unsigned(j));
            plan.constant = plan.constant && !depends_on(e, varying);
            plan.numeric = plan.numeric && GiNaC::is_a<GiNaC::numeric>(e);
            identity = identity && e.is_equal(i == j ? ex(1) : ex(0));
        }
    plan.blocks = coupled_blocks(M);
    std::size_t largest = 0;
    for (const auto& b : plan.blocks) largest = std::max(largest, b.size());
    using Method = SolvePlan::Method;
    plan.method = identity                         ? Method::identity
                  : largest == 1                   ? Method::diagonal
                  : largest > unrolled_limit       ? Method::eigen_llt
                  : plan.blocks.size() > 1         ? Method::block_diagonal
                                                   : Method::unrolled_ldlt;
    // A numeric M is factored here: a zero pivot is known now.
    if (plan.numeric && plan.method != Method::eigen_llt) {
        Block probe;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) probe.outputs.push_back(M(unsigned(i), unsigned(j)));
        for (std::size_t i = 0; i < n; ++i) probe.outputs.push_back(0);
        solve_block(probe, plan, n, 1, "probe");
    }
    return plan;
}

namespace {

// X = M⁻¹B in straight-line code appended to `code`, `plan` being plan_solve's for M: `m_at(i, j)`
// gives M's entries, `rhs_at(i, c)` B's (n × columns). What the solve reads is named first, so that
// its operations stay the system's; `solve_ops` gets the solve's own. `free_of_solve[i][c]` says
// where M_kk cancelled from f_k (no more than f_k, which the system counts).
std::vector<std::vector<ex>> solve_mass(StraightLine& code, const SolvePlan& plan, std::size_t n, std::size_t columns,
                                        const std::function<ex(std::size_t, std::size_t)>& m_at,
                                        const std::function<ex(std::size_t, std::size_t)>& rhs_at,
                                        std::vector<std::vector<bool>>& free_of_solve, std::size_t& solve_ops) {
    using Method = SolvePlan::Method;
    std::vector<std::vector<ex>> x(n, std::vector<ex>(columns));
    free_of_solve.assign(n, std::vector<bool>(columns, false));
    solve_ops = 0;
    if (plan.method == Method::identity) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < columns; ++c) x[i][c] = rhs_at(i, c);
        return x;
    }
    std::vector<std::vector<ex>> a(n, std::vector<ex>(n)), b(n, std::vector<ex>(columns));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < columns; ++c) b[i][c] = code.name(rhs_at(i, c));
    for (const auto& block : plan.blocks)
        for (std::size_t r = 0; r < block.size(); ++r)
            for (std::size_t s = 0; s <= r; ++s) a[block[r]][block[s]] = code.name(m_at(block[r], block[s]));
    const std::size_t first = code.size();
    for (const auto& block : plan.blocks) {
        if (block.size() == 1) {
            const std::size_t i = block[0];
            if (a[i][i].is_zero())
                throw EmitError(fmt::format("the mass matrix is singular: its diagonal entry {0} is zero and row {0} "
                                            "has no other entry",
                                            i));
            // M_kk's factors cancel from f_k's where both are products at the top (a particle's
            // m from m·g, so a constant M costs nothing at run time); otherwise one division per
            // entry, several right-hand sides sharing one reciprocal. GiNaC's product cancels
            // m·g·m⁻¹ by itself; M_kk ≠ 0 is the plan's premise either way.
            const ex inverse = GiNaC::pow(m_at(i, i), -1);
            ex scale;
            for (std::size_t c = 0; c < columns; ++c) {
                const ex cancelled = rhs_at(i, c) * inverse;
                if (count_operations(cancelled) <= count_operations(rhs_at(i, c))) {
                    x[i][c] = cancelled;
                    free_of_solve[i][c] = true;
                    continue;
                }
                if (scale.is_zero()) scale = columns == 1 ? GiNaC::pow(a[i][i], -1) : code.reciprocal(a[i][i]);
                x[i][c] = b[i][c] * scale;
            }
            continue;
        }
        std::vector<std::vector<ex>> ab(block.size(), std::vector<ex>(block.size())), bb;
        for (std::size_t r = 0; r < block.size(); ++r) {
            for (std::size_t s = 0; s <= r; ++s) ab[r][s] = a[block[r]][block[s]];
            bb.push_back(b[block[r]]);
        }
        solve_dense(code, block, ab, bb, x);
    }
    for (std::size_t k = first; k < code.size(); ++k) solve_ops += count_operations(code.block().temporaries[k].value);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < columns; ++c)
            if (!free_of_solve[i][c]) solve_ops += count_operations(x[i][c]);
    return x;
}

void require_straight_line(const SolvePlan& plan, const char* who) {
    if (plan.method == SolvePlan::Method::none || plan.method == SolvePlan::Method::eigen_llt)
        throw std::logic_error(std::string(who) + ": no straight-line solve for this plan");
}

}  // namespace

Block solve_block(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t columns,
                  const std::string& prefix) {
    require_straight_line(plan, "solve_block");
    if (system.outputs.size() != n * n + n * columns)
        throw std::logic_error("solve_block: the system has " + std::to_string(system.outputs.size()) +
                               " outputs for M and " + std::to_string(columns) + " right-hand sides of size " +
                               std::to_string(n));
    Block bare = system;
    bare.outputs.clear();
    StraightLine code(std::move(bare), prefix);
    std::vector<std::vector<bool>> free_of_solve;
    std::size_t solve_ops = 0;
    const auto x = solve_mass(
        code, plan, n, columns, [&](std::size_t i, std::size_t j) { return system.outputs[i * n + j]; },
        [&](std::size_t i, std::size_t c) { return system.outputs[n * n + i * columns + c]; }, free_of_solve, solve_ops);
    Block& out = code.block();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < columns; ++c) out.outputs.push_back(x[i][c]);
    count_outputs(out, system.ops_before, solve_ops);
    return std::move(out);
}

Block reduce_programs(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m, std::size_t k,
                      const std::string& prefix) {
    require_straight_line(plan, "reduce_programs");
    if (system.outputs.size() != n * n + n + m * n + m + n * k)
        throw std::logic_error("reduce_programs: the system has " + std::to_string(system.outputs.size()) +
                               " outputs for M, f, Ā, c and D");
    const std::size_t f_at = n * n, a_at = f_at + n, c_at = a_at + m * n, d_at = c_at + m;
    Block bare = system;
    bare.outputs.clear();
    StraightLine code(std::move(bare), prefix);
    std::vector<std::vector<bool>> free_of_solve;
    std::size_t solve_ops = 0;
    // [z | Y] = M⁻¹ [f | D]: column 0 is f, columns 1 … k are D's.
    const auto zy = solve_mass(
        code, plan, n, 1 + k, [&](std::size_t i, std::size_t j) { return system.outputs[i * n + j]; },
        [&](std::size_t i, std::size_t c) { return c == 0 ? system.outputs[f_at + i] : system.outputs[d_at + i * k + c - 1]; },
        free_of_solve, solve_ops);
    // G = Ā Y and h = c − Ā z read every entry of z, Y and Ā several times: each is named once (their
    // operations are counted already, the solve's or the system's).
    std::vector<std::vector<ex>> x(n, std::vector<ex>(1 + k));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c <= k; ++c) x[i][c] = code.name(zy[i][c]);
    std::vector<ex> A(m * n);
    for (std::size_t e = 0; e < m * n; ++e) A[e] = code.name(system.outputs[a_at + e]);
    Block& out = code.block();
    for (std::size_t i = 0; i < n; ++i) out.outputs.push_back(x[i][0]);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t b = 0; b < k; ++b) out.outputs.push_back(x[i][1 + b]);
    std::vector<ex> products;
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < k; ++b) {
            ex g = 0;
            for (std::size_t i = 0; i < n; ++i) g += A[a * n + i] * x[i][1 + b];
            products.push_back(g);
        }
    for (std::size_t a = 0; a < m; ++a) {
        ex h = system.outputs[c_at + a];
        for (std::size_t i = 0; i < n; ++i) h -= A[a * n + i] * x[i][0];
        products.push_back(h);
    }
    for (const ex& e : products) solve_ops += count_operations(e);
    out.outputs.insert(out.outputs.end(), products.begin(), products.end());
    for (std::size_t e = 0; e < n * k; ++e) out.outputs.push_back(system.outputs[d_at + e]);
    count_outputs(out, system.ops_before, solve_ops);
    return std::move(out);
}

SolvePlan plan_saddle_point(const GiNaC::matrix& M, const std::vector<ex>& W, std::size_t m,
                            const std::vector<ex>& varying) {
    const std::size_t n = M.rows();
    const GiNaC::matrix K = saddle_point_matrix(M, W, m);
    SolvePlan plan;
    plan.constant = true;
    plan.numeric = true;
    for (std::size_t i = 0; i < n + m; ++i)
        for (std::size_t j = 0; j < n + m; ++j) {
            const ex& e = K(unsigned(i), unsigned(j));
            plan.constant = plan.constant && !depends_on(e, varying);
            plan.numeric = plan.numeric && GiNaC::is_a<GiNaC::numeric>(e);
        }
    plan.blocks = coupled_blocks(K);
    std::size_t largest = 0;
    for (const auto& b : plan.blocks) {
        largest = std::max(largest, b.size());
        if (b.size() == 1 && b[0] >= n)
            throw EmitError(fmt::format("constraint row {} constrains no velocity (its W is zero)", b[0] - n));
    }
    using Method = SolvePlan::Method;
    plan.method = largest > unrolled_limit ? Method::eigen_llt : plan.blocks.size() > 1 ? Method::block_diagonal
                                                                                         : Method::unrolled_ldlt;
    // A numeric K is factored here: dependent rows show as a zero pivot now.
    if (plan.numeric && plan.method != Method::eigen_llt) {
        StraightLine probe(Block{}, "probe");
        std::vector<std::vector<ex>> named;
        std::size_t first = 0;
        solve_saddle(probe, plan, n + m, [&](std::size_t i, std::size_t j) { return K(unsigned(i), unsigned(j)); },
                     std::vector<std::vector<ex>>(n + m, std::vector<ex>(1, 0)), named, first);
    }
    return plan;
}

Block solve_saddle_point(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m,
                         const std::string& prefix) {
    require_straight_line(plan, "solve_saddle_point");
    if (system.outputs.size() != n * n + n + m * n + m)
        throw std::logic_error("solve_saddle_point: the system has " + std::to_string(system.outputs.size()) +
                               " outputs for M, f, W and r");
    const auto out = [&](std::size_t k) { return system.outputs[k]; };
    const auto lower = saddle_lower(system, n, n * n + n);
    std::vector<std::vector<ex>> rhs(n + m, std::vector<ex>(1));
    for (std::size_t k = 0; k < n; ++k) rhs[k][0] = out(n * n + k);
    for (std::size_t a = 0; a < m; ++a) rhs[n + a][0] = out(n * n + n + m * n + a);
    Block bare = system;
    bare.outputs.clear();
    StraightLine code(std::move(bare), prefix);
    std::size_t first = 0;
    std::vector<std::vector<ex>> K;
    const auto x = solve_saddle(code, plan, n + m, lower, rhs, K, first);
    // λ = −(the multipliers' unknowns), named once: the reactions read it again.
    std::vector<ex> lambda(m);
    for (std::size_t a = 0; a < m; ++a) lambda[a] = code.name(-x[n + a][0]);
    Block& result = code.block();
    for (std::size_t k = 0; k < n; ++k) result.outputs.push_back(x[k][0]);
    for (std::size_t a = 0; a < m; ++a) result.outputs.push_back(lambda[a]);
    for (std::size_t k = 0; k < n; ++k) {  // (Wᵀλ)_k, W's entries as the solve named them
        ex reaction = 0;
        for (std::size_t a = 0; a < m; ++a) reaction += K[n + a][k] * lambda[a];
        result.outputs.push_back(reaction);
    }
    count_solve(result, system.ops_before, first);
    return std::move(result);
}

Block saddle_point_correction(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m,
                              const std::string& prefix) {
    require_straight_line(plan, "saddle_point_correction");
    if (system.outputs.size() != n * n + m * n)
        throw std::logic_error("saddle_point_correction: the system has " + std::to_string(system.outputs.size()) +
                               " outputs for M and W");
    const auto lower = saddle_lower(system, n, n * n);
    // K [du; μ] = [0; e_j]: M du + Wᵀμ = 0 and W du = e_j, so du = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ e_j.
    std::vector<std::vector<ex>> unit(n + m, std::vector<ex>(m, 0));
    for (std::size_t a = 0; a < m; ++a) unit[n + a][a] = 1;
    Block bare = system;
    bare.outputs.clear();
    StraightLine code(std::move(bare), prefix);
    std::size_t first = 0;
    std::vector<std::vector<ex>> K;
    const auto x = solve_saddle(code, plan, n + m, lower, unit, K, first);
    Block& result = code.block();
    for (std::size_t k = 0; k < n; ++k)
        for (std::size_t a = 0; a < m; ++a) result.outputs.push_back(x[k][a]);
    count_solve(result, system.ops_before, first);
    return std::move(result);
}

std::string describe(const SolvePlan& plan, std::size_t n_velocities) {
    using Method = SolvePlan::Method;
    std::string blocks;
    for (const auto& b : plan.blocks) {
        if (b.size() < 2) continue;
        std::string members;
        for (std::size_t i : b) members += (members.empty() ? "" : ", ") + std::to_string(i);
        blocks += (blocks.empty() ? "" : ", ") + ("{" + members + "}");
    }
    const std::string constant = plan.numeric    ? " M is constant (numbers only): its factors were computed at generation time."
                                 : plan.constant ? " M is constant (parameters only)."
                                                 : "";
    switch (plan.method) {
        case Method::none:
            return "";
        case Method::identity:
            return "Solve of M u̇ = f: identity (M = I, u̇ = f; no solve at run time).";
        case Method::diagonal:
            return "Solve of M u̇ = f: diagonal (u̇_k = f_k / M_kk)." + constant;
        case Method::block_diagonal:
            return "Solve of M u̇ = f: block-diagonal (blocks " + blocks +
                   " by unrolled LDLᵀ in straight-line code, the other velocities by division)." + constant;
        case Method::unrolled_ldlt:
            return fmt::format("Solve of M u̇ = f: unrolled LDLᵀ in straight-line code (n_velocities = {} ≤ {}).",
                               n_velocities, unrolled_limit) +
                   constant;
        case Method::eigen_llt:
            return fmt::format("Solve of M u̇ = f: Eigen LLT at run time (a block of {} velocities > {}).",
                               [&] {
                                   std::size_t largest = 0;
                                   for (const auto& b : plan.blocks) largest = std::max(largest, b.size());
                                   return largest;
                               }(),
                               unrolled_limit) +
                   (plan.constant ? " M is constant, factored at run time all the same." : "");
    }
    return "";
}

}  // namespace eomc::codegen
