// The solve of M u̇ = f planned from M's structure (codegen/solve_plan.hpp): which path each
// structure gets, what the banner calls it, and the straight-line solve's values.
//
// Exact: with rational entries GiNaC's arithmetic is exact, so the straight-line solve of a
// random symmetric positive definite M must give M⁻¹B exactly (GiNaC's matrix inverse as the
// reference).
//
// Double: the same straight-line code evaluated in IEEE double (GiNaC's double-floats: every
// operation rounded to double) against Eigen's LLT on the same double M and B. Both are backward
// stable: the computed x̂ solves (M + ΔM) x̂ = b with ‖ΔM‖₂ ≤ n γ_{3n+1} ‖M‖₂, γ_k = k u/(1 − k u)
// (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., Thm. 10.4 with
// ‖|Rᵀ||R|‖₂ ≤ n ‖M‖₂; LDLᵀ is the same arithmetic with the square roots moved into D). Each
// is then within κ₂ ε/(1 − κ₂ ε) ≤ 2 κ₂ ε of the exact solution when ε = n γ_{3n+1} and
// κ₂ ε ≤ 1/2, so the two differ by at most 4 κ₂ n γ_{3n+1} relative to ‖x‖₂, column by column.
#define BOOST_TEST_MODULE codegen_solve_plan
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "codegen/solve_plan.hpp"

using namespace eomc;
using GiNaC::ex;
using Method = codegen::SolvePlan::Method;

namespace {

// A symmetric positive definite matrix with the given blocks (velocity index sets): within a
// block M = G Gᵀ + I over random integers G in [1, 3] (so that every entry of a block is
// nonzero: the block is coupled), zero between blocks.
GiNaC::matrix random_spd(std::size_t n, const std::vector<std::vector<std::size_t>>& blocks, std::mt19937& gen) {
    std::uniform_int_distribution<int> entry(1, 3);
    GiNaC::matrix M{unsigned(n), unsigned(n)};
    for (const auto& b : blocks) {
        const std::size_t s = b.size();
        std::vector<std::vector<int>> G(s, std::vector<int>(s));
        for (auto& row : G)
            for (int& v : row) v = entry(gen);
        for (std::size_t i = 0; i < s; ++i)
            for (std::size_t j = 0; j < s; ++j) {
                int v = i == j ? 1 : 0;
                for (std::size_t k = 0; k < s; ++k) v += G[i][k] * G[j][k];
                M(unsigned(b[i]), unsigned(b[j])) = v;
            }
    }
    return M;
}

std::vector<std::vector<std::size_t>> one_block(std::size_t n) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    return {all};
}

// The system block of the solve: M's entries as symbols m_i_j (the same symbol for (i, j) and
// (j, i): M is symmetric), zero where M is, then B's as symbols b_i_c.
struct SymbolicSystem {
    codegen::Block block;
    GiNaC::matrix M;  // over the m symbols
    std::vector<std::vector<GiNaC::symbol>> m, b;
};

SymbolicSystem symbolic_system(const GiNaC::matrix& pattern, std::size_t columns) {
    const std::size_t n = pattern.rows();
    SymbolicSystem s{{}, GiNaC::matrix(unsigned(n), unsigned(n)), {}, {}};
    s.m.assign(n, std::vector<GiNaC::symbol>(n));
    s.b.assign(n, std::vector<GiNaC::symbol>(columns));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j <= i; ++j) {
            s.m[i][j] = s.m[j][i] = GiNaC::symbol("m_" + std::to_string(i) + "_" + std::to_string(j));
            const ex entry = pattern(unsigned(i), unsigned(j)).is_zero() ? ex(0) : ex(s.m[i][j]);
            s.M(unsigned(i), unsigned(j)) = s.M(unsigned(j), unsigned(i)) = entry;
        }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) s.block.outputs.push_back(s.M(unsigned(i), unsigned(j)));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < columns; ++c) {
            s.b[i][c] = GiNaC::symbol("b_" + std::to_string(i) + "_" + std::to_string(c));
            s.block.outputs.push_back(s.b[i][c]);
        }
    return s;
}

// The plan of a matrix over the m symbols when every one of them varies (a state-dependent M).
codegen::SolvePlan varying_plan(const SymbolicSystem& s) {
    std::vector<ex> varying;
    for (const auto& row : s.m)
        for (const auto& v : row) varying.push_back(v);
    return codegen::plan_solve(s.M, varying);
}

// The outputs of a block with its input symbols bound to numbers: each temporary once, in order.
std::vector<GiNaC::numeric> evaluate(const codegen::Block& block, GiNaC::exmap values) {
    for (const auto& t : block.temporaries) {
        const ex v = t.value.subs(values);
        BOOST_TEST_REQUIRE(GiNaC::is_a<GiNaC::numeric>(v), "temporary " << t.symbol << " = " << v << " is not a number");
        values[t.symbol] = v;
    }
    std::vector<GiNaC::numeric> out;
    for (const ex& o : block.outputs) {
        const ex v = o.subs(values);
        BOOST_TEST_REQUIRE(GiNaC::is_a<GiNaC::numeric>(v), "output " << o << " = " << v << " is not a number");
        out.push_back(GiNaC::ex_to<GiNaC::numeric>(v));
    }
    return out;
}

// X = M⁻¹B from the straight-line solve, with M and B bound to exact integers, against GiNaC's
// exact inverse.
void check_exact(const GiNaC::matrix& M_values, std::size_t columns, std::mt19937& gen) {
    const std::size_t n = M_values.rows();
    const SymbolicSystem s = symbolic_system(M_values, columns);
    const codegen::SolvePlan plan = varying_plan(s);
    const codegen::Block solved = codegen::solve_block(s.block, plan, n, columns, "w");
    std::uniform_int_distribution<int> entry(-9, 9);
    GiNaC::exmap values;
    GiNaC::matrix B{unsigned(n), unsigned(columns)};
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j <= i; ++j) values[s.m[i][j]] = M_values(unsigned(i), unsigned(j));
        for (std::size_t c = 0; c < columns; ++c) values[s.b[i][c]] = B(unsigned(i), unsigned(c)) = entry(gen);
    }
    const GiNaC::matrix X = M_values.inverse().mul(B);
    const std::vector<GiNaC::numeric> x = evaluate(solved, values);
    BOOST_TEST_REQUIRE(x.size() == n * columns);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < columns; ++c)
            BOOST_TEST((x[i * columns + c] - X(unsigned(i), unsigned(c))).is_zero(),
                       "x(" << i << ", " << c << ") = " << x[i * columns + c] << ", exactly " << X(unsigned(i), unsigned(c)));
}

double gamma(std::size_t k) {
    const double u = std::numeric_limits<double>::epsilon() / 2;
    return double(k) * u / (1 - double(k) * u);
}

// The straight-line solve evaluated in double against Eigen's LLT on the same double M and B, within
// 4 κ₂ n γ_{3n+1} (the header's bound). Returns the largest ratio of difference to bound.
double check_double(const std::vector<std::vector<std::size_t>>& blocks, std::size_t n, std::size_t columns,
                    std::mt19937& gen) {
    std::normal_distribution<double> normal;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
    for (const auto& b : blocks) {
        const auto s = Eigen::Index(b.size());
        Eigen::MatrixXd G(s, s);
        for (Eigen::Index i = 0; i < s; ++i)
            for (Eigen::Index j = 0; j < s; ++j) G(i, j) = normal(gen);
        // Eigenvalues from 0.1 to O(s): κ₂ of a few hundred, enough to see an unstable solve.
        const Eigen::MatrixXd A = G * G.transpose() + 0.1 * Eigen::MatrixXd::Identity(s, s);
        for (Eigen::Index i = 0; i < s; ++i)
            for (Eigen::Index j = 0; j < s; ++j) M(Eigen::Index(b[std::size_t(i)]), Eigen::Index(b[std::size_t(j)])) = A(i, j);
    }
    Eigen::MatrixXd B{Eigen::Index(n), Eigen::Index(columns)};
    for (Eigen::Index i = 0; i < B.rows(); ++i)
        for (Eigen::Index c = 0; c < B.cols(); ++c) B(i, c) = normal(gen);

    GiNaC::matrix pattern{unsigned(n), unsigned(n)};
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) pattern(unsigned(i), unsigned(j)) = M(Eigen::Index(i), Eigen::Index(j)) != 0 ? 1 : 0;
    const SymbolicSystem s = symbolic_system(pattern, columns);
    const codegen::Block solved = codegen::solve_block(s.block, varying_plan(s), n, columns, "w");
    GiNaC::exmap values;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j <= i; ++j) values[s.m[i][j]] = GiNaC::numeric(M(Eigen::Index(i), Eigen::Index(j)));
        for (std::size_t c = 0; c < columns; ++c) values[s.b[i][c]] = GiNaC::numeric(B(Eigen::Index(i), Eigen::Index(c)));
    }
    const std::vector<GiNaC::numeric> x = evaluate(solved, values);
    const Eigen::LLT<Eigen::MatrixXd> llt(M);
    BOOST_TEST_REQUIRE(llt.info() == Eigen::Success);
    const Eigen::MatrixXd reference = llt.solve(B);
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues();
    const double kappa = lambda.maxCoeff() / lambda.minCoeff(), eps = double(n) * gamma(3 * n + 1);
    BOOST_TEST_REQUIRE(kappa * eps <= 0.5);
    const double bound = 4 * kappa * eps;
    double worst = 0;
    for (std::size_t c = 0; c < columns; ++c) {
        Eigen::VectorXd diff{Eigen::Index(n)};
        for (std::size_t i = 0; i < n; ++i)
            diff(Eigen::Index(i)) = x[i * columns + c].to_double() - reference(Eigen::Index(i), Eigen::Index(c));
        const double relative = diff.norm() / reference.col(Eigen::Index(c)).norm();
        BOOST_TEST(relative <= bound, "n = " << n << ", column " << c << ": relative difference " << relative
                                             << " > 4 κ₂ n γ_{3n+1} = " << bound << " (κ₂ = " << kappa << ")");
        worst = std::max(worst, relative / bound);
    }
    return worst;
}

std::size_t divisions(const codegen::Block& block) {
    std::size_t count = 0;
    const auto visit = [&](const ex& e, const auto& self) -> void {
        if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
            GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_negative())
            ++count;
        for (std::size_t i = 0; i < e.nops(); ++i) self(e.op(i), self);
    };
    for (const auto& t : block.temporaries) visit(t.value, visit);
    for (const ex& o : block.outputs) visit(o, visit);
    return count;
}

}  // namespace

BOOST_AUTO_TEST_CASE(each_structure_gets_its_path_and_the_banner_names_it) {
    std::mt19937 gen(19);
    {
        const GiNaC::matrix I = GiNaC::ex_to<GiNaC::matrix>(GiNaC::unit_matrix(4));
        const auto plan = codegen::plan_solve(I, {});
        BOOST_TEST(int(plan.method) == int(Method::identity));
        BOOST_TEST(plan.constant);
        BOOST_TEST(plan.numeric);
        BOOST_TEST(codegen::describe(plan, 4) == "Solve of M u̇ = f: identity (M = I, u̇ = f; no solve at run time).");
    }
    {
        const SymbolicSystem s = symbolic_system(random_spd(5, {{0}, {1}, {2}, {3}, {4}}, gen), 1);
        const auto plan = varying_plan(s);
        BOOST_TEST(int(plan.method) == int(Method::diagonal));
        BOOST_TEST(!plan.constant);
        BOOST_TEST(codegen::describe(plan, 5) == "Solve of M u̇ = f: diagonal (u̇_k = f_k / M_kk).");
    }
    {
        // Blocks of permuted velocities: {0, 3, 5}, {1, 6}, {2}, {4}.
        const SymbolicSystem s = symbolic_system(random_spd(7, {{0, 3, 5}, {1, 6}, {2}, {4}}, gen), 1);
        const auto plan = varying_plan(s);
        BOOST_TEST(int(plan.method) == int(Method::block_diagonal));
        const std::vector<std::vector<std::size_t>> expected{{0, 3, 5}, {1, 6}, {2}, {4}};
        BOOST_TEST((plan.blocks == expected));
        BOOST_TEST(codegen::describe(plan, 7) ==
                   "Solve of M u̇ = f: block-diagonal (blocks {0, 3, 5}, {1, 6} by unrolled LDLᵀ in straight-line code, "
                   "the other velocities by division).");
    }
    for (std::size_t n : {std::size_t(2), std::size_t(8), codegen::unrolled_limit}) {
        const auto plan = varying_plan(symbolic_system(random_spd(n, one_block(n), gen), 1));
        BOOST_TEST(int(plan.method) == int(Method::unrolled_ldlt));
        BOOST_TEST(codegen::describe(plan, n).find("Solve of M u̇ = f: unrolled LDLᵀ in straight-line code") == 0);
    }
    {
        // One block past the limit: Eigen, and no straight-line solve.
        const std::size_t n = codegen::unrolled_limit + 1;
        const SymbolicSystem s = symbolic_system(random_spd(n + 1, {one_block(n)[0], {n}}, gen), 1);
        const auto plan = varying_plan(s);
        BOOST_TEST(int(plan.method) == int(Method::eigen_llt));
        BOOST_TEST(codegen::describe(plan, n + 1).find("Solve of M u̇ = f: Eigen LLT at run time (a block of " +
                                                       std::to_string(n) + " velocities") == 0);
        BOOST_CHECK_THROW(codegen::solve_block(s.block, plan, n + 1, 1, "w"), std::logic_error);
    }
}

BOOST_AUTO_TEST_CASE(constant_matrices_are_recognised_and_a_numeric_one_is_factored_at_generation_time) {
    // M over parameters (m1, m2) and numbers: constant; over a state q as well: not.
    const GiNaC::symbol m1("m1"), m2("m2"), q("q");
    // T of three masses in relative coordinates (x1, x2 − x1, x3 − x2)
    GiNaC::matrix relative{{m1 + m2 + 2, m2 + 2, 2}, {m2 + 2, m2 + 2, 2}, {2, 2, 2}};
    auto plan = codegen::plan_solve(relative, {q});
    BOOST_TEST(plan.constant);
    BOOST_TEST(!plan.numeric);
    BOOST_TEST(int(plan.method) == int(Method::unrolled_ldlt));
    BOOST_TEST(codegen::describe(plan, 3).find("M is constant (parameters only).") != std::string::npos);
    relative(0, 0) = m1 + m2 + 2 + GiNaC::cos(q);
    BOOST_TEST(!codegen::plan_solve(relative, {q}).constant);

    // Numbers only: the factors are numbers, so the solve is u̇ = (a constant matrix) f with no
    // division left for run time, and exact.
    const GiNaC::matrix numeric{{6, 4, 2}, {4, 4, 2}, {2, 2, 2}};
    plan = codegen::plan_solve(numeric, {q});
    BOOST_TEST(plan.numeric);
    BOOST_TEST(codegen::describe(plan, 3).find("its factors were computed at generation time") != std::string::npos);
    codegen::Block system;
    GiNaC::symbol f0("f0"), f1("f1"), f2("f2");
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j) system.outputs.push_back(numeric(i, j));
    system.outputs.insert(system.outputs.end(), {f0 * q, f1, f2});
    const codegen::Block solved = codegen::solve_block(system, plan, 3, 1, "w");
    BOOST_TEST(divisions(solved) == 0u);
    const GiNaC::matrix exact = numeric.inverse().mul(GiNaC::matrix{{f0 * q}, {f1}, {f2}});
    GiNaC::exmap temporaries;
    for (const auto& t : solved.temporaries) temporaries[t.symbol] = t.value.subs(temporaries);
    for (unsigned i = 0; i < 3; ++i)
        BOOST_TEST((solved.outputs[i].subs(temporaries) - exact(i, 0)).expand().is_zero(), "u̇_" << i);
}

BOOST_AUTO_TEST_CASE(a_particle_mass_cancels_from_its_force_so_a_constant_diagonal_m_costs_no_division) {
    // Two bodies under mutual gravity in Cartesian coordinates (one axis each, enough for the
    // structure): M = diag(m1, m2), f_k = m_k · (field at body k). u̇_k = f_k / m_k is the field
    // itself, so the kernel divides by no mass; where f_k has no factor m_k (a force not
    // proportional to the mass) the division stays, exact.
    const GiNaC::symbol m1("m1"), m2("m2"), G("G"), x1("x1"), x2("x2"), F("F");
    const GiNaC::matrix M{{m1, 0}, {0, m2}};
    const auto plan = codegen::plan_solve(M, {x1, x2});
    BOOST_TEST(int(plan.method) == int(Method::diagonal));
    BOOST_TEST(plan.constant);
    const ex r3 = GiNaC::pow(GiNaC::pow(x2 - x1, 2), GiNaC::numeric(3, 2));
    const ex field1 = G * m2 * (x2 - x1) / r3, field2 = -G * m1 * (x2 - x1) / r3;
    codegen::Block system;
    system.outputs = {m1, 0, 0, m2, m1 * field1, m2 * field2};
    codegen::Block solved = codegen::solve_block(system, plan, 2, 1, "w");
    BOOST_TEST((solved.outputs[0] - field1).expand().is_zero());
    BOOST_TEST((solved.outputs[1] - field2).expand().is_zero());
    for (const ex& e : solved.outputs) BOOST_TEST(!e.has(GiNaC::pow(m1, -1)), e);
    BOOST_TEST(!solved.outputs[1].has(GiNaC::pow(m2, -1)));

    // A force that is not a multiple of the mass keeps its one division.
    system.outputs = {m1, 0, 0, m2, F, m2 * field2};
    solved = codegen::solve_block(system, plan, 2, 1, "w");
    BOOST_TEST((solved.outputs[0] - F / m1).expand().is_zero());
    BOOST_TEST((solved.outputs[1] - field2).expand().is_zero());
    BOOST_TEST(divisions(solved) >= 1u);
}

BOOST_AUTO_TEST_CASE(the_straight_line_solve_is_exact_in_exact_arithmetic) {
    std::mt19937 gen(20261126);
    for (std::size_t n = 1; n <= codegen::unrolled_limit; ++n)
        for (std::size_t columns : {std::size_t(1), 2 * n}) check_exact(random_spd(n, one_block(n), gen), columns, gen);
    check_exact(random_spd(7, {{0, 3, 5}, {1, 6}, {2}, {4}}, gen), 1, gen);
    check_exact(random_spd(7, {{0, 3, 5}, {1, 6}, {2}, {4}}, gen), 14, gen);
    check_exact(random_spd(4, {{0}, {1}, {2}, {3}}, gen), 8, gen);
    check_exact(GiNaC::ex_to<GiNaC::matrix>(GiNaC::unit_matrix(3)), 2, gen);
}

BOOST_AUTO_TEST_CASE(the_straight_line_solve_agrees_with_eigen_to_round_off_in_double) {
    std::mt19937 gen(1126);
    double worst = 0;
    for (int repeat = 0; repeat < 3; ++repeat) {
        for (std::size_t n = 1; n <= codegen::unrolled_limit; ++n)
            worst = std::max(worst, check_double(one_block(n), n, repeat == 0 ? 1 : n, gen));
        worst = std::max(worst, check_double({{0, 3, 5}, {1, 6}, {2}, {4}}, 7, 2, gen));
        worst = std::max(worst, check_double({{0}, {1}, {2}}, 3, 1, gen));
    }
    BOOST_TEST_MESSAGE("largest difference / bound: " << worst);
}

namespace {

// The saddle-point solve of M u̇ − Wᵀλ = f, W u̇ = r over symbols (M's entries where the pattern
// has them, W's where the row pattern has them, f, r), bound to exact integers: u̇, λ and Wᵀλ
// against GiNaC's exact solve of the bordered matrix, and the projection's correction C against
// M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹.
void check_saddle_point_exact(const GiNaC::matrix& M_values, const std::vector<std::vector<int>>& W_values,
                              std::mt19937& gen) {
    const std::size_t n = M_values.rows(), m = W_values.size();
    const SymbolicSystem s = symbolic_system(M_values, 1);  // M then f = b_i_0
    std::vector<std::vector<GiNaC::symbol>> w(m, std::vector<GiNaC::symbol>(n));
    std::vector<GiNaC::symbol> r;
    std::vector<ex> W, varying;
    for (const auto& row : s.m)
        for (const auto& v : row) varying.push_back(v);
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t k = 0; k < n; ++k) {
            w[a][k] = GiNaC::symbol("w_" + std::to_string(a) + "_" + std::to_string(k));
            W.push_back(W_values[a][k] == 0 ? ex(0) : ex(w[a][k]));
            varying.push_back(w[a][k]);
        }
    codegen::Block system = s.block;
    system.outputs.insert(system.outputs.end(), W.begin(), W.end());
    for (std::size_t a = 0; a < m; ++a) {
        r.emplace_back("r_" + std::to_string(a));
        system.outputs.push_back(r.back());
    }
    const codegen::SolvePlan plan = codegen::plan_saddle_point(s.M, W, m, varying);
    BOOST_TEST_REQUIRE(int(plan.method) != int(Method::eigen_llt));
    const codegen::Block solved = codegen::solve_saddle_point(system, plan, n, m, "w");
    BOOST_TEST_REQUIRE(solved.outputs.size() == n + m + n);

    std::uniform_int_distribution<int> entry(-9, 9);
    GiNaC::exmap values;
    GiNaC::matrix K{unsigned(n + m), unsigned(n + m)}, rhs{unsigned(n + m), 1};
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) K(unsigned(i), unsigned(j)) = M_values(unsigned(i), unsigned(j));
        for (std::size_t j = 0; j <= i; ++j) values[s.m[i][j]] = M_values(unsigned(i), unsigned(j));
        values[s.b[i][0]] = rhs(unsigned(i), 0) = entry(gen);
    }
    for (std::size_t a = 0; a < m; ++a) {
        for (std::size_t k = 0; k < n; ++k) {
            values[w[a][k]] = W_values[a][k];
            K(unsigned(n + a), unsigned(k)) = K(unsigned(k), unsigned(n + a)) = W_values[a][k];
        }
        values[r[a]] = rhs(unsigned(n + a), 0) = entry(gen);
    }
    // K (u̇, −λ) = (f, r).
    const GiNaC::matrix exact = K.inverse().mul(rhs);
    const auto got = evaluate(solved, values);
    for (std::size_t k = 0; k < n; ++k) BOOST_TEST((got[k] - exact(unsigned(k), 0)).is_zero(), "u̇_" << k);
    for (std::size_t a = 0; a < m; ++a) BOOST_TEST((got[n + a] + exact(unsigned(n + a), 0)).is_zero(), "λ_" << a);
    for (std::size_t k = 0; k < n; ++k) {
        GiNaC::numeric reaction = 0;
        for (std::size_t a = 0; a < m; ++a) reaction += W_values[a][k] * got[n + a];
        BOOST_TEST((got[n + m + k] - reaction).is_zero(), "(Wᵀλ)_" << k);
    }

    // C from the block of M and W alone.
    codegen::Block mw = s.block;
    mw.outputs.resize(n * n);
    mw.outputs.insert(mw.outputs.end(), W.begin(), W.end());
    const codegen::Block correction = codegen::saddle_point_correction(mw, plan, n, m, "w");
    GiNaC::matrix Mn{unsigned(n), unsigned(n)}, Wt{unsigned(n), unsigned(m)};
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) Mn(unsigned(i), unsigned(j)) = M_values(unsigned(i), unsigned(j));
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t k = 0; k < n; ++k) Wt(unsigned(k), unsigned(a)) = W_values[a][k];
    const GiNaC::matrix Y = Mn.inverse().mul(Wt);
    const GiNaC::matrix C = Y.mul(Wt.transpose().mul(Y).inverse());
    const auto c = evaluate(correction, values);
    BOOST_TEST_REQUIRE(c.size() == n * m);
    for (std::size_t k = 0; k < n; ++k)
        for (std::size_t a = 0; a < m; ++a)
            BOOST_TEST((c[k * m + a] - C(unsigned(k), unsigned(a))).is_zero(), "C_" << k << "," << a);
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_saddle_point_solve_of_constraint_rows_is_exact_in_exact_arithmetic) {
    std::mt19937 gen(20261126);
    std::uniform_int_distribution<int> entry(-3, 3);
    // Full row rank W with every entry nonzero (one coupled block), m = 1 .. min(n, 4).
    for (std::size_t n = 1; n <= 8; ++n)
        for (std::size_t m = 1; m <= std::min<std::size_t>(n, 4); ++m) {
            std::vector<std::vector<int>> W(m, std::vector<int>(n));
            for (std::size_t a = 0; a < m; ++a)
                for (std::size_t k = 0; k < n; ++k) W[a][k] = (a == k % m ? 5 : 0) + (entry(gen) == 0 ? 1 : entry(gen));
            check_saddle_point_exact(random_spd(n, one_block(n), gen), W, gen);
        }
    // A diagonal M and a row touching some velocities only: the others stay single blocks (u̇ = f/M).
    check_saddle_point_exact(random_spd(5, {{0}, {1}, {2}, {3}, {4}}, gen), {{1, 0, -2, 0, 0}}, gen);
    // Two rows on disjoint velocities: two coupled blocks.
    check_saddle_point_exact(random_spd(4, {{0}, {1}, {2}, {3}}, gen), {{1, 2, 0, 0}, {0, 0, 3, -1}}, gen);
}

BOOST_AUTO_TEST_CASE(constraint_rows_it_cannot_solve_are_refused_at_generation_time) {
    const GiNaC::symbol q("q");
    const GiNaC::matrix M{{2, 0}, {0, 3}};
    // A row with no velocity in it.
    BOOST_CHECK_EXCEPTION(codegen::plan_saddle_point(M, {0, 0}, 1, {q}), codegen::EmitError,
                          [](const codegen::EmitError& e) { return std::string(e.what()).find("constrains no velocity") != std::string::npos; });
    // Two equal rows: W has rank 1, the second multiplier's pivot is 0.
    BOOST_CHECK_EXCEPTION(codegen::plan_saddle_point(M, {1, 1, 1, 1}, 2, {q}), codegen::EmitError,
                          [](const codegen::EmitError& e) { return std::string(e.what()).find("dependent") != std::string::npos; });
    // Past unrolled_limit coupled unknowns: the runtime's Schur complement.
    const std::size_t n = codegen::unrolled_limit;
    GiNaC::matrix big{unsigned(n), unsigned(n)};
    std::vector<ex> row(n, 1);
    for (std::size_t i = 0; i < n; ++i) big(unsigned(i), unsigned(i)) = 1;
    BOOST_TEST(int(codegen::plan_saddle_point(big, row, 1, {q}).method) == int(Method::eigen_llt));
}

BOOST_AUTO_TEST_CASE(matrices_it_cannot_solve_are_refused_at_generation_time) {
    const GiNaC::symbol a("a"), b("b"), q("q");
    // Not symmetric.
    BOOST_CHECK_THROW(codegen::plan_solve(GiNaC::matrix{{1, a}, {b, 1}}, {q}), codegen::EmitError);
    // Numeric and singular: a zero pivot, found while factoring at generation time.
    BOOST_CHECK_THROW(codegen::plan_solve(GiNaC::matrix{{1, 1, 0}, {1, 1, 0}, {0, 0, 1}}, {q}), codegen::EmitError);
    // A velocity with no inertia at all.
    BOOST_CHECK_THROW(codegen::plan_solve(GiNaC::matrix{{1, 0, 0}, {0, 0, 0}, {0, 0, 1}}, {q}), codegen::EmitError);
    // Symmetric once expanded is symmetric.
    const auto plan = codegen::plan_solve(GiNaC::matrix{{2, a * (q + 1)}, {a * q + a, 2}}, {q});
    BOOST_TEST(int(plan.method) == int(Method::unrolled_ldlt));
}

namespace {

// The reduction of programs M u̇ = f + D λ, Ā u̇ = c (reduce_programs) over symbols for M (where the
// pattern has entries), f, Ā, c and D, bound to exact integers: z, Y, G, h and D against GiNaC's
// exact M⁻¹, and the λ and u̇ they give against the exact solve of [[M, −D], [Ā, 0]] (u̇, λ) = (f, c).
void check_programs_exact(const GiNaC::matrix& M_values, std::size_t m, std::mt19937& gen) {
    const std::size_t n = M_values.rows(), k = m;
    const SymbolicSystem s = symbolic_system(M_values, 1);  // M then f = b_i_0
    codegen::Block system = s.block;
    std::vector<GiNaC::symbol> a_sym, c_sym, d_sym;
    for (std::size_t e = 0; e < m * n; ++e) system.outputs.push_back(a_sym.emplace_back("a_" + std::to_string(e)));
    for (std::size_t e = 0; e < m; ++e) system.outputs.push_back(c_sym.emplace_back("c_" + std::to_string(e)));
    for (std::size_t e = 0; e < n * k; ++e) system.outputs.push_back(d_sym.emplace_back("d_" + std::to_string(e)));
    const codegen::SolvePlan plan = varying_plan(s);
    const codegen::Block reduced = codegen::reduce_programs(system, plan, n, m, k, "w");
    BOOST_TEST_REQUIRE(reduced.outputs.size() == n + n * k + m * k + m + n * k);

    // Ā and D random with |det(Ā M⁻¹ D)| > 0 (redrawn otherwise), f and c random.
    std::uniform_int_distribution<int> entry(-5, 5);
    GiNaC::matrix A{unsigned(m), unsigned(n)}, D{unsigned(n), unsigned(k)}, f{unsigned(n), 1}, c{unsigned(m), 1};
    const GiNaC::matrix Minv = M_values.inverse();
    do {
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < n; ++j) A(unsigned(i), unsigned(j)) = entry(gen);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < k; ++j) D(unsigned(i), unsigned(j)) = entry(gen);
    } while (A.mul(Minv).mul(D).determinant().is_zero());
    GiNaC::exmap values;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j <= i; ++j) values[s.m[i][j]] = M_values(unsigned(i), unsigned(j));
        values[s.b[i][0]] = f(unsigned(i), 0) = entry(gen);
    }
    for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = 0; j < n; ++j) values[a_sym[i * n + j]] = A(unsigned(i), unsigned(j));
        values[c_sym[i]] = c(unsigned(i), 0) = entry(gen);
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < k; ++j) values[d_sym[i * k + j]] = D(unsigned(i), unsigned(j));

    const GiNaC::matrix z = Minv.mul(f), Y = Minv.mul(D), G = A.mul(Y), h = c.sub(A.mul(z));
    const auto got = evaluate(reduced, values);
    std::size_t at = 0;
    const auto expect = [&](const GiNaC::matrix& X, const char* what) {
        for (unsigned i = 0; i < X.rows(); ++i)
            for (unsigned j = 0; j < X.cols(); ++j, ++at)
                BOOST_TEST((got[at] - X(i, j)).is_zero(), what << "(" << i << ", " << j << ") = " << got[at] << ", exactly "
                                                               << X(i, j));
    };
    expect(z, "z");
    expect(Y, "Y");
    expect(G, "G");
    expect(h, "h");
    expect(D, "D");

    // λ = G⁻¹h and u̇ = z + Y λ solve the bordered system.
    GiNaC::matrix K{unsigned(n + m), unsigned(n + k)}, rhs{unsigned(n + m), 1};
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) K(unsigned(i), unsigned(j)) = M_values(unsigned(i), unsigned(j));
        for (std::size_t j = 0; j < k; ++j) K(unsigned(i), unsigned(n + j)) = -D(unsigned(i), unsigned(j));
        rhs(unsigned(i), 0) = f(unsigned(i), 0);
    }
    for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = 0; j < n; ++j) K(unsigned(n + i), unsigned(j)) = A(unsigned(i), unsigned(j));
        rhs(unsigned(n + i), 0) = c(unsigned(i), 0);
    }
    const GiNaC::matrix exact = K.inverse().mul(rhs), lambda = G.inverse().mul(h), udot = z.add(Y.mul(lambda));
    for (std::size_t i = 0; i < n; ++i) BOOST_TEST((udot(unsigned(i), 0) - exact(unsigned(i), 0)).is_zero(), "u̇_" << i);
    for (std::size_t a = 0; a < m; ++a)
        BOOST_TEST((lambda(unsigned(a), 0) - exact(unsigned(n + a), 0)).is_zero(), "λ_" << a);
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_reduction_of_programs_is_exact_in_exact_arithmetic) {
    std::mt19937 gen(3261126);
    for (std::size_t n = 1; n <= 6; ++n)
        for (std::size_t m = 1; m <= std::min<std::size_t>(n, 3); ++m) check_programs_exact(random_spd(n, one_block(n), gen), m, gen);
    // Diagonal and block-diagonal M take their own paths through the same reduction.
    check_programs_exact(random_spd(4, {{0}, {1}, {2}, {3}}, gen), 2, gen);
    check_programs_exact(random_spd(5, {{0, 2}, {1}, {3, 4}}, gen), 3, gen);
}
