// The polynomial integral search (Mei, Special Topics in Analytical Mechanics, ch. 5) on the
// Euler–Poisson equations written out by hand here (not taken from the library), in the
// conventions γ = upward vertical in body axes, r_c = (x0, y0, z0), weight P, ω = (p, q, r):
//   A ṗ = (B − C) q r + P (z0 γ2 − y0 γ3),  B q̇ = (C − A) r p + P (x0 γ3 − z0 γ1),
//   C ṙ = (A − B) p q + P (y0 γ1 − x0 γ2),  γ̇ = γ × ω,
// with the classical integrals H (energy), K_z (area) and Γ = |γ|². The cases:
//   * Kovalevskaya (A = B = 2C, r_c on the equator): one new integral at degree 4, K
//     (Kovalevskaya 1889, Acta Math. 12), none at degree 3;
//   * Goryachev–Chaplygin (A = B = 4C): none unconditional at degree 3, one on K_z = 0
//     (Goryachev 1900; Chaplygin 1901), G = r(p² + q²) − (P x0/C) p γ3, dG/dt = −(P x0/C) q K_z;
//   * Lagrange (A = B, r_c on the symmetry axis): r at degree 1;
//   * Euler (r_c = 0): |Iω|² at degree 2, then nothing more at degree 4;
//   * a generic heavy body: nothing at degree 4.
// Also: the same output whatever order the symbols were created in, the decimals of the scenes
// as exact rationals, and the refusals.
#define BOOST_TEST_MODULE integral_search
#include <boost/test/unit_test.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "mechanics/rigid/integral_search.hpp"

namespace rigid = eomc::mechanics::rigid;
using GiNaC::ex;
using GiNaC::numeric;
using GiNaC::symbol;

namespace {

struct Body {
    numeric A, B, C, P, x0 = 0, y0 = 0, z0 = 0;
};

struct EulerPoisson {
    std::vector<symbol> state;  // p, q, r, γ1, γ2, γ3
    std::vector<ex> field;
    ex H, Kz, Gamma;
    symbol p, q, r, g1, g2, g3;
};

// The symbols are created in the order given by `creation` (a permutation of 0..5), so the
// serials, hence GiNaC's internal order, differ between two builds of the same field.
EulerPoisson euler_poisson(const Body& b, std::vector<int> creation = {0, 1, 2, 3, 4, 5}) {
    static const char* names[] = {"p", "q", "r", "g1", "g2", "g3"};
    std::vector<symbol> made(6);
    for (int i : creation) made[std::size_t(i)] = symbol(names[i]);
    EulerPoisson e{made, {}, 0, 0, 0, made[0], made[1], made[2], made[3], made[4], made[5]};
    const ex p = e.p, q = e.q, r = e.r, g1 = e.g1, g2 = e.g2, g3 = e.g3;
    e.field = {((b.B - b.C) * q * r + b.P * (b.z0 * g2 - b.y0 * g3)) / b.A,
               ((b.C - b.A) * r * p + b.P * (b.x0 * g3 - b.z0 * g1)) / b.B,
               ((b.A - b.B) * p * q + b.P * (b.y0 * g1 - b.x0 * g2)) / b.C,
               g2 * r - g3 * q,
               g3 * p - g1 * r,
               g1 * q - g2 * p};
    e.H = (b.A * p * p + b.B * q * q + b.C * r * r) / 2 + b.P * (b.x0 * g1 + b.y0 * g2 + b.z0 * g3);
    e.Kz = b.A * p * g1 + b.B * q * g2 + b.C * r * g3;
    e.Gamma = g1 * g1 + g2 * g2 + g3 * g3;
    return e;
}

rigid::IntegralSearchInput input_of(const EulerPoisson& e, unsigned degree) {
    rigid::IntegralSearchInput in;
    in.state = e.state;
    in.field = e.field;
    in.degree = degree;
    in.known = {{"energy", e.H}, {"area", e.Kz}, {"gamma", e.Gamma}};
    return in;
}

// dF/dt along the field, by GiNaC's own diff (independent of the library's arithmetic).
ex rate(const EulerPoisson& e, const ex& F) {
    ex out = 0;
    for (std::size_t i = 0; i < e.state.size(); ++i) out += F.diff(e.state[i]) * e.field[i];
    return out.expand();
}

// The coefficients of a polynomial in the state, one per monomial.
void coefficients(const ex& e, const std::vector<symbol>& x, std::size_t i, GiNaC::lst& out) {
    if (i == x.size()) {
        out.append(e == 0);
        return;
    }
    const int d = e.degree(x[i]);
    for (int k = 0; k <= d; ++k) coefficients(e.coeff(x[i], k).expand(), x, i + 1, out);
}

// Whether F − λ·target − Σ a_j basis_j = 0 has a solution, with λ ≠ 0 when target is given.
bool in_span(const ex& F, const ex& target, const std::vector<ex>& basis, const std::vector<symbol>& x) {
    symbol lambda("lambda");
    GiNaC::lst unknowns{lambda};
    ex residual = F - lambda * target;
    for (std::size_t j = 0; j < basis.size(); ++j) {
        std::string name = "a";
        name += std::to_string(j);  // not "a" + …: GCC 12's false -Wrestrict
        symbol a(name);
        unknowns.append(a);
        residual -= a * basis[j];
    }
    GiNaC::lst equations;
    coefficients(residual.expand(), x, 0, equations);
    const ex solution = GiNaC::lsolve(equations, unknowns);
    if (solution.nops() == 0) return false;
    if (target.is_zero()) return true;
    for (const auto& s : solution)
        if (s.lhs() == lambda) return !s.rhs().is_zero() && !GiNaC::has(s.rhs(), lambda);
    return false;
}

// 1, H, K_z, Γ and their products up to degree 4 (each is of degree 2).
std::vector<ex> known_algebra(const EulerPoisson& e, const std::vector<ex>& extra = {}) {
    std::vector<ex> k{e.H, e.Kz, e.Gamma};
    k.insert(k.end(), extra.begin(), extra.end());
    std::vector<ex> out{1};
    for (std::size_t i = 0; i < k.size(); ++i) {
        out.push_back(k[i]);
        for (std::size_t j = i; j < k.size(); ++j) out.push_back((k[i] * k[j]).expand());
    }
    return out;
}

const Body kovalevskaya{1, 1, numeric(1, 2), 1, 1};
const Body goryachev_chaplygin{1, 1, numeric(1, 4), 1, 1};

}  // namespace

BOOST_AUTO_TEST_CASE(kovalevskaya_degree_4_finds_K) {
    const auto e = euler_poisson(kovalevskaya);
    const auto start = std::chrono::steady_clock::now();
    const auto found = rigid::search_polynomial_integrals(input_of(e, 4));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    BOOST_TEST_MESSAGE("Kovalevskaya, degree 4: " << seconds << " s");
    BOOST_REQUIRE_EQUAL(found.size(), 1u);
    BOOST_TEST(!found[0].conditional);
    BOOST_TEST(found[0].degree == 4u);
    BOOST_TEST(rate(e, found[0].value).is_zero());
    // K = (p² − q² − c γ1)² + (2pq − c γ2)², c = P x0 / C = 2: an integral, and the one found up
    // to a nonzero multiple and the known algebra.
    const ex c = kovalevskaya.P * kovalevskaya.x0 / kovalevskaya.C;
    const ex K = GiNaC::pow(e.p * e.p - e.q * e.q - c * e.g1, 2) + GiNaC::pow(2 * e.p * e.q - c * e.g2, 2);
    BOOST_TEST(rate(e, K).is_zero());
    BOOST_TEST(in_span(found[0].value, K, known_algebra(e), e.state));
    BOOST_TEST(!in_span(K, 0, known_algebra(e), e.state));
    BOOST_TEST_MESSAGE("found: " << found[0].value);
}

BOOST_AUTO_TEST_CASE(kovalevskaya_degree_3_finds_nothing) {
    const auto e = euler_poisson(kovalevskaya);
    BOOST_TEST(rigid::search_polynomial_integrals(input_of(e, 3)).empty());
}

BOOST_AUTO_TEST_CASE(goryachev_chaplygin_on_zero_area) {
    const auto e = euler_poisson(goryachev_chaplygin);
    auto in = input_of(e, 3);
    in.conditions = {{"area", e.Kz, 0}};
    const auto found = rigid::search_polynomial_integrals(in);
    BOOST_REQUIRE_EQUAL(found.size(), 1u);
    const auto& f = found[0];
    BOOST_TEST_MESSAGE("found: " << f.value << ", d/dt = (" << f.cofactor << ")·K_z");
    BOOST_TEST(f.conditional);
    BOOST_TEST(f.condition_name == "holds on area = 0");
    BOOST_TEST(f.degree == 3u);
    BOOST_TEST(!f.cofactor.is_zero());
    BOOST_TEST((rate(e, f.value) - f.cofactor * e.Kz).expand().is_zero());
    // G by hand, with dG/dt = −(P x0 / C) q K_z exactly.
    const ex c = goryachev_chaplygin.P * goryachev_chaplygin.x0 / goryachev_chaplygin.C;
    const ex G = e.r * (e.p * e.p + e.q * e.q) - c * e.p * e.g3;
    BOOST_TEST((rate(e, G) + c * e.q * e.Kz).expand().is_zero());
    // The one found is G up to a nonzero multiple, the known algebra and K_z·(linear).
    std::vector<ex> trivial{1, e.H, e.Kz, e.Gamma};
    for (const auto& x : e.state) trivial.push_back((e.Kz * x).expand());
    BOOST_TEST(in_span(f.value, G, trivial, e.state));
    // Without the condition: nothing.
    BOOST_TEST(rigid::search_polynomial_integrals(input_of(e, 3)).empty());
}

BOOST_AUTO_TEST_CASE(lagrange_top_finds_r) {
    const auto e = euler_poisson({numeric(3, 2), numeric(3, 2), numeric(3, 5), 2, 0, 0, numeric(1, 4)});
    const auto found = rigid::search_polynomial_integrals(input_of(e, 1));
    BOOST_REQUIRE_EQUAL(found.size(), 1u);
    BOOST_TEST(found[0].degree == 1u);
    BOOST_TEST((found[0].value - e.r).expand().is_zero());  // canonical: primitive, leading > 0
}

BOOST_AUTO_TEST_CASE(euler_case_angular_momentum) {
    const auto e = euler_poisson({1, 2, 3, 1});
    const auto found = rigid::search_polynomial_integrals(input_of(e, 2));
    BOOST_REQUIRE_EQUAL(found.size(), 1u);
    BOOST_TEST(found[0].degree == 2u);
    const ex L2 = GiNaC::pow(e.p, 2) + 4 * GiNaC::pow(e.q, 2) + 9 * GiNaC::pow(e.r, 2);  // |Iω|²
    BOOST_TEST(rate(e, L2).is_zero());
    BOOST_TEST(in_span(found[0].value, L2, {1, e.H, e.Kz, e.Gamma}, e.state));
    auto in = input_of(e, 4);
    in.known.push_back({"angular momentum", L2});
    BOOST_TEST(rigid::search_polynomial_integrals(in).empty());
}

BOOST_AUTO_TEST_CASE(generic_heavy_body_has_nothing_new) {
    const auto e = euler_poisson({1, 2, 3, 1, 1, 1, 1});
    BOOST_TEST(rigid::search_polynomial_integrals(input_of(e, 4)).empty());
}

BOOST_AUTO_TEST_CASE(deterministic) {
    // Same input twice, and the same field from symbols created in reverse order: the same
    // integrals, term by term, once the symbols are matched by name.
    const auto compare = [](const Body& b, unsigned degree, bool area) {
        const auto e1 = euler_poisson(b), e2 = euler_poisson(b, {5, 4, 3, 2, 1, 0});
        auto in1 = input_of(e1, degree), in2 = input_of(e2, degree);
        if (area) {
            in1.conditions = {{"area", e1.Kz, 0}};
            in2.conditions = {{"area", e2.Kz, 0}};
        }
        const auto a = rigid::search_polynomial_integrals(in1), again = rigid::search_polynomial_integrals(in1),
                   c = rigid::search_polynomial_integrals(in2);
        GiNaC::exmap rename;
        for (std::size_t i = 0; i < 6; ++i) rename[e2.state[i]] = e1.state[i];
        BOOST_REQUIRE_EQUAL(a.size(), again.size());
        BOOST_REQUIRE_EQUAL(a.size(), c.size());
        BOOST_REQUIRE(!a.empty());
        for (std::size_t i = 0; i < a.size(); ++i) {
            BOOST_TEST(a[i].value.is_equal(again[i].value));
            BOOST_TEST(a[i].cofactor.is_equal(again[i].cofactor));
            BOOST_TEST((a[i].value - c[i].value.subs(rename)).expand().is_zero());
            BOOST_TEST((a[i].cofactor - c[i].cofactor.subs(rename)).expand().is_zero());
            BOOST_TEST(a[i].condition_name == c[i].condition_name);
        }
    };
    compare(kovalevskaya, 4, false);
    compare(goryachev_chaplygin, 3, true);
}

BOOST_AUTO_TEST_CASE(decimals_as_rationals) {
    BOOST_TEST(*rigid::rational_from_decimal(0.5) == numeric(1, 2));
    BOOST_TEST(*rigid::rational_from_decimal(0.1) == numeric(1, 10));
    BOOST_TEST(*rigid::rational_from_decimal(2.5e-3) == numeric(1, 400));
    BOOST_TEST(*rigid::rational_from_decimal(-1.25) == numeric(-5, 4));
    BOOST_TEST(*rigid::rational_from_decimal(3.0) == numeric(3));
    BOOST_TEST(*rigid::rational_from_decimal(0.0) == numeric(0));
    BOOST_TEST(*rigid::rational_from_decimal(1e20) == numeric(10).power(20));
    BOOST_TEST(!rigid::rational_from_decimal(1.0 / 3.0));
    BOOST_TEST(!rigid::rational_from_decimal(std::numeric_limits<double>::quiet_NaN()));
    BOOST_TEST(!rigid::rational_from_decimal(std::numeric_limits<double>::infinity()));
}

BOOST_AUTO_TEST_CASE(refusals) {
    const auto e = euler_poisson(kovalevskaya);
    auto in = input_of(e, 2);
    symbol P("P");
    in.field[2] = P * e.g2;  // a parameter left as a symbol
    BOOST_CHECK_THROW(rigid::search_polynomial_integrals(in), std::invalid_argument);
    in = input_of(e, 2);
    in.known.push_back({"not one", e.p});
    BOOST_CHECK_THROW(rigid::search_polynomial_integrals(in), std::invalid_argument);
    in = input_of(e, 2);
    in.field.pop_back();
    BOOST_CHECK_THROW(rigid::search_polynomial_integrals(in), std::invalid_argument);
    in = input_of(e, 2);
    in.field[0] = GiNaC::sin(e.p);
    BOOST_CHECK_THROW(rigid::search_polynomial_integrals(in), std::invalid_argument);
}
