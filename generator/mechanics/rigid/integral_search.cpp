#include "mechanics/rigid/integral_search.hpp"

#include <cln/integer.h>
#include <cln/rational.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>
#include <set>
#include <stdexcept>
#include <utility>

#include "symbolic/differentiation.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;

namespace {

// CLN's rationals directly, not GiNaC::numeric: every numeric operation allocates a GiNaC
// object, and the elimination below does millions of them (Kovalevskaya at degree 4: 462
// equations in 210 unknowns).
using Rational = cln::cl_RA;
using Exponents = std::vector<unsigned>;

unsigned total_degree(const Exponents& e) {
    unsigned d = 0;
    for (unsigned k : e) d += k;
    return d;
}

// Graded lexicographic order, highest first: total degree, then the exponent of x_1, of x_2, ….
// A monomial order (compatible with products), so division by one polynomial below is exact
// whenever it divides; and it sees only exponent vectors, never GiNaC's symbol serials.
struct HigherFirst {
    bool operator()(const Exponents& a, const Exponents& b) const {
        const unsigned da = total_degree(a), db = total_degree(b);
        if (da != db) return da > db;
        return a > b;
    }
};

using Polynomial = std::map<Exponents, Rational, HigherFirst>;

void add_term(Polynomial& p, const Exponents& e, const Rational& c) {
    if (cln::zerop(c)) return;
    auto [it, inserted] = p.emplace(e, c);
    if (inserted) return;
    it->second = it->second + c;
    if (cln::zerop(it->second)) p.erase(it);
}

// a += f·b
void add_multiple(Polynomial& a, const Rational& f, const Polynomial& b) {
    for (const auto& [e, c] : b) add_term(a, e, f * c);
}

Polynomial product(const Polynomial& a, const Polynomial& b) {
    Polynomial out;
    for (const auto& [ea, ca] : a)
        for (const auto& [eb, cb] : b) {
            Exponents e = ea;
            for (std::size_t i = 0; i < e.size(); ++i) e[i] += eb[i];
            add_term(out, e, ca * cb);
        }
    return out;
}

unsigned degree_of(const Polynomial& p) { return p.empty() ? 0 : total_degree(p.begin()->first); }

Rational rational_of(const GiNaC::numeric& n) { return cln::the<cln::cl_RA>(n.to_cl_N()); }

// e, expanded, as a polynomial in the state; throws when it is not one with rational
// coefficients (a parameter left as a symbol, a sin, a negative power).
Polynomial polynomial_of(const ex& e, const std::vector<GiNaC::symbol>& state, const std::string& what) {
    std::map<ex, std::size_t, GiNaC::ex_is_less> index;
    for (std::size_t i = 0; i < state.size(); ++i) index.emplace(state[i], i);
    const auto refuse = [&](const ex& part) {
        std::ostringstream s;
        s << what << " is not a polynomial in the state with rational coefficients (at " << part << ")";
        throw std::invalid_argument(s.str());
    };
    const ex expanded = e.expand();
    Polynomial p;
    const auto add_monomial = [&](const ex& term) {
        Exponents exps(state.size(), 0);
        Rational c = 1;
        const auto factor = [&](const ex& f) {
            if (GiNaC::is_a<GiNaC::numeric>(f)) {
                const auto& n = GiNaC::ex_to<GiNaC::numeric>(f);
                if (!n.is_rational()) refuse(f);
                c = c * rational_of(n);
                return;
            }
            ex base = f;
            unsigned k = 1;
            if (GiNaC::is_a<GiNaC::power>(f)) {
                const ex exponent = f.op(1);
                if (!GiNaC::is_a<GiNaC::numeric>(exponent) || !GiNaC::ex_to<GiNaC::numeric>(exponent).is_pos_integer()) refuse(f);
                base = f.op(0);
                k = unsigned(GiNaC::ex_to<GiNaC::numeric>(exponent).to_int());
            }
            const auto it = index.find(base);
            if (it == index.end()) refuse(f);
            exps[it->second] += k;
        };
        if (GiNaC::is_a<GiNaC::mul>(term))
            for (const auto& f : term) factor(f);
        else
            factor(term);
        add_term(p, exps, c);
    };
    if (GiNaC::is_a<GiNaC::add>(expanded))
        for (const auto& term : expanded) add_monomial(term);
    else if (!expanded.is_zero())
        add_monomial(expanded);
    return p;
}

ex expression_of(const Polynomial& p, const std::vector<GiNaC::symbol>& state) {
    ex out = 0;
    for (const auto& [e, c] : p) {
        ex term = GiNaC::numeric(c);
        for (std::size_t i = 0; i < e.size(); ++i)
            if (e[i] != 0) term *= GiNaC::pow(state[i], e[i]);
        out += term;
    }
    return out;
}

// dF/dt = Σ ∂F/∂x_i f_i.
Polynomial rate_of(const Polynomial& F, const std::vector<Polynomial>& field) {
    Polynomial out;
    for (const auto& [e, c] : F)
        for (std::size_t i = 0; i < e.size(); ++i) {
            if (e[i] == 0) continue;
            Exponents lowered = e;
            --lowered[i];
            add_multiple(out, c * Rational(int(e[i])), product(Polynomial{{lowered, 1}}, field[i]));
        }
    return out;
}

// h / g when g divides h exactly; nullopt otherwise. Dividing by the leading term is exact for
// one divisor ({g} is a Gröbner basis of the ideal (g)).
std::optional<Polynomial> exact_quotient(Polynomial h, const Polynomial& g) {
    Polynomial q;
    const auto& [lead, lead_c] = *g.begin();
    while (!h.empty()) {
        const auto [e, c] = *h.begin();
        Exponents t = e;
        for (std::size_t i = 0; i < t.size(); ++i) {
            if (t[i] < lead[i]) return std::nullopt;
            t[i] -= lead[i];
        }
        const Rational f = c / lead_c;
        add_term(q, t, f);
        add_multiple(h, -f, product(Polynomial{{t, 1}}, g));
    }
    return q;
}

// All exponent vectors of n variables with total degree ≤ d, highest first.
std::vector<Exponents> monomials_up_to(std::size_t n, int d) {
    std::vector<Exponents> out;
    if (d < 0) return out;
    Exponents e(n, 0);
    const auto fill = [&](auto&& self, std::size_t i, unsigned left) -> void {
        if (i == n) {
            out.push_back(e);
            return;
        }
        for (unsigned k = 0; k <= left; ++k) {
            e[i] = k;
            self(self, i + 1, left - k);
        }
        e[i] = 0;
    };
    fill(fill, 0, unsigned(d));
    std::sort(out.begin(), out.end(), HigherFirst{});
    return out;
}

// Sparse rows over the rationals, entries sorted by column.
using Row = std::vector<std::pair<std::size_t, Rational>>;

// a − f·b
Row minus_multiple(const Row& a, const Rational& f, const Row& b) {
    Row out;
    out.reserve(a.size() + b.size());
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        if (j == b.size() || (i < a.size() && a[i].first < b[j].first)) {
            out.push_back(a[i++]);
        } else if (i == a.size() || b[j].first < a[i].first) {
            out.emplace_back(b[j].first, -f * b[j].second);
            ++j;
        } else {
            Rational v = a[i].second - f * b[j].second;
            if (!cln::zerop(v)) out.emplace_back(a[i].first, std::move(v));
            ++i, ++j;
        }
    }
    return out;
}

// The elimination's work in entry operations (one a − f·b per entry of a and b): what the search
// is budgeted in, a count rather than a clock so the verdict is the same on every machine.
class WorkMeter {
public:
    explicit WorkMeter(std::size_t budget) : budget_(budget) {}
    void spend(std::size_t entries) {
        spent_ += entries;
        if (budget_ && spent_ > budget_) throw SearchBudgetExhausted(spent_);
    }
    std::size_t spent() const { return spent_; }

private:
    std::size_t budget_, spent_ = 0;
};

// Row echelon form built one row at a time; reduced() gives the reduced row echelon form, the
// one basis of the row space with each leading entry 1 and zeros above and below it (unique,
// so the reported integrals do not depend on the order rows came in).
class Echelon {
public:
    explicit Echelon(WorkMeter& work) : work_(work) {}

    bool insert(Row r) {
        while (!r.empty()) {
            const auto it = rows_.find(r.front().first);
            if (it == rows_.end()) break;
            const Rational f = r.front().second;
            work_.spend(r.size() + it->second.size());
            r = minus_multiple(r, f, it->second);
        }
        if (r.empty()) return false;
        const Rational lead = r.front().second;
        for (auto& [col, v] : r) v = v / lead;
        rows_.emplace(r.front().first, std::move(r));
        return true;
    }

    // Back substitution from the last pivot up: a fully reduced row holds no pivot column but
    // its own, so subtracting it never brings back a pivot already cleared.
    std::map<std::size_t, Row> reduced() const {
        std::map<std::size_t, Row> out;
        for (auto it = rows_.rbegin(); it != rows_.rend(); ++it) {
            Row r = it->second;
            for (const auto& [col, v0] : it->second) {
                if (col == it->first) continue;
                const auto p = out.find(col);
                if (p == out.end()) continue;
                const auto at = std::lower_bound(r.begin(), r.end(), col, [](const auto& e, std::size_t c) { return e.first < c; });
                if (at == r.end() || at->first != col) continue;
                const Rational f = at->second;
                work_.spend(r.size() + p->second.size());
                r = minus_multiple(r, f, p->second);
            }
            out.emplace(it->first, std::move(r));
        }
        return out;
    }

    std::set<std::size_t> pivots() const {
        std::set<std::size_t> out;
        for (const auto& [col, r] : rows_) out.insert(col);
        return out;
    }

private:
    WorkMeter& work_;
    std::map<std::size_t, Row> rows_;
};

// The monomials of degree ≤ d as coordinates.
struct Basis {
    std::vector<Exponents> monomials;
    std::map<Exponents, std::size_t, HigherFirst> index;

    Basis(std::size_t n, unsigned d) : monomials(monomials_up_to(n, int(d))) {
        for (std::size_t j = 0; j < monomials.size(); ++j) index.emplace(monomials[j], j);
    }
    Row row_of(const Polynomial& p) const {
        Row r;
        for (const auto& [e, c] : p) r.emplace_back(index.at(e), c);
        return r;  // the order is the map's, which is the index's
    }
    Polynomial polynomial_of(const Row& r) const {
        Polynomial p;
        for (const auto& [j, c] : r) p.emplace(monomials[j], c);
        return p;
    }
};

// The null space of the equations (rows over `columns` unknowns), as a basis.
std::vector<Row> null_space(const std::vector<Row>& equations, std::size_t columns, WorkMeter& work) {
    Echelon e(work);
    for (const auto& r : equations) e.insert(r);
    const auto rref = e.reduced();
    // x_free = 1, x_pivot = −R[pivot][free] for each free column.
    std::map<std::size_t, Row> kernel;
    for (std::size_t j = 0; j < columns; ++j)
        if (!rref.count(j)) kernel[j].emplace_back(j, 1);
    for (const auto& [pivot, r] : rref)
        for (const auto& [j, v] : r)
            if (j != pivot) kernel.at(j).emplace_back(pivot, -v);
    std::vector<Row> out;
    for (auto& [j, r] : kernel) {
        std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        out.push_back(std::move(r));
    }
    return out;
}

// Equations Σ_j c_j L(m_j) + Σ_k λ_k (extra_k) = 0, one per monomial of the result, as rows
// over the unknowns (c, λ), in the monomials' order.
std::vector<Row> equations_of(const std::vector<Polynomial>& columns) {
    std::map<Exponents, Row, HigherFirst> rows;
    for (std::size_t j = 0; j < columns.size(); ++j)
        for (const auto& [e, c] : columns[j]) rows[e].emplace_back(j, c);
    std::vector<Row> out;
    for (auto& [e, r] : rows) out.push_back(std::move(r));
    return out;
}

// The rows of span(solutions)'s reduced echelon basis whose leading monomial no element of
// span(trivial) has: a basis of solutions modulo trivial (trivial ⊆ solutions), and the
// canonical one, since both leading-monomial sets and the reduced basis are unique.
std::vector<Row> complement(const std::vector<Row>& solutions, const std::vector<Row>& trivial, WorkMeter& work) {
    Echelon s(work), t(work);
    for (const auto& r : solutions) s.insert(r);
    for (const auto& r : trivial) t.insert(r);
    const auto taken = t.pivots();
    std::vector<Row> out;
    for (auto& [pivot, r] : s.reduced())
        if (!taken.count(pivot)) out.push_back(std::move(r));
    return out;
}

// Primitive integers with a positive leading coefficient: the printed form of an integral.
Polynomial primitive(Polynomial p) {
    cln::cl_I denominators = 1, numerators = 0;
    for (const auto& [e, c] : p) {
        denominators = cln::lcm(denominators, cln::denominator(c));
        numerators = cln::gcd(numerators, cln::numerator(c));
    }
    Rational f = Rational(denominators) / Rational(numerators);
    if (cln::minusp(p.begin()->second)) f = -f;
    for (auto& [e, c] : p) c = c * f;
    return p;
}

std::string level_text(const GiNaC::numeric& level) {
    std::ostringstream s;
    s << level;
    return s.str();
}

// The products Π K_i^{a_i} of total degree ≤ d (1 included): the known algebra's spanning set.
std::vector<Polynomial> known_products(const std::vector<Polynomial>& known, unsigned d, std::size_t n) {
    std::vector<Polynomial> out;
    const auto grow = [&](auto&& self, std::size_t i, const Polynomial& so_far, unsigned degree) -> void {
        if (i == known.size()) {
            out.push_back(so_far);
            return;
        }
        const unsigned k = degree_of(known[i]);
        Polynomial power = so_far;
        for (unsigned used = degree;;) {
            self(self, i + 1, power, used);
            if (k == 0 || used + k > d) break;  // a constant known adds nothing to the span
            power = product(power, known[i]);
            used += k;
        }
    };
    grow(grow, 0, Polynomial{{Exponents(n, 0), 1}}, 0);
    return out;
}

// The symbolic confirmation, in GiNaC's own arithmetic: expand(dF/dt − Λ·g) is exactly 0.
void confirm(const ex& F, const ex& cofactor, const ex& g, const IntegralSearchInput& input) {
    ex rate = 0;
    for (std::size_t i = 0; i < input.state.size(); ++i) rate += symbolic::derivative(F, input.state[i]) * input.field[i];
    if (!(rate - cofactor * g).expand().is_zero()) {
        std::ostringstream s;
        s << "integral search: " << F << " failed its symbolic confirmation";
        throw std::logic_error(s.str());
    }
}

}  // namespace

std::vector<FoundIntegral> search_polynomial_integrals(const IntegralSearchInput& input, std::size_t* work_spent) {
    const std::size_t n = input.state.size();
    if (input.field.size() != n)
        throw std::invalid_argument("integral search: the field has " + std::to_string(input.field.size()) +
                                    " components for " + std::to_string(n) + " state variables");
    {
        std::set<ex, GiNaC::ex_is_less> distinct(input.state.begin(), input.state.end());
        if (distinct.size() != n) throw std::invalid_argument("integral search: a state variable is listed twice");
    }
    std::vector<Polynomial> field;
    unsigned field_degree = 0;
    for (std::size_t i = 0; i < n; ++i) {
        field.push_back(polynomial_of(input.field[i], input.state, "component " + std::to_string(i + 1) + " of the field"));
        field_degree = std::max(field_degree, degree_of(field.back()));
    }
    const auto integral_of = [&](const ex& value, const std::string& name) {
        Polynomial p = polynomial_of(value, input.state, name);
        const Polynomial rate = rate_of(p, field);
        if (!rate.empty()) {
            std::ostringstream s;
            s << "integral search: " << name << " is not a first integral (d/dt = " << expression_of(rate, input.state) << ")";
            throw std::invalid_argument(s.str());
        }
        return p;
    };
    std::vector<Polynomial> known;
    for (const auto& k : input.known) known.push_back(integral_of(k.value, "known integral " + k.name));

    const unsigned d = input.degree;
    WorkMeter work(input.work_budget);
    const Basis F_basis(n, d);
    std::vector<Polynomial> rates;
    for (const auto& m : F_basis.monomials) rates.push_back(rate_of(Polynomial{{m, 1}}, field));

    // The known algebra up to degree d: always integrals, never new.
    std::vector<Row> trivial;
    for (const auto& p : known_products(known, d, n))
        if (degree_of(p) <= d) trivial.push_back(F_basis.row_of(p));

    std::vector<FoundIntegral> found;
    const std::vector<Row> integrals = null_space(equations_of(rates), F_basis.monomials.size(), work);
    for (const auto& r : complement(integrals, trivial, work)) {
        const Polynomial F = primitive(F_basis.polynomial_of(r));
        FoundIntegral f;
        f.value = expression_of(F, input.state);
        f.degree = degree_of(F);
        f.cofactor = 0;
        confirm(f.value, 0, 0, input);
        found.push_back(std::move(f));
    }

    for (const auto& c : input.conditions) {
        Polynomial g = integral_of(c.value, "condition " + c.name);
        add_term(g, Exponents(n, 0), -rational_of(c.level));
        const unsigned deg_g = degree_of(g);
        if (g.empty() || deg_g == 0) throw std::invalid_argument("integral search: condition " + c.name + " is a constant");
        // dF/dt has degree ≤ d − 1 + deg f, so Λ has degree ≤ d − 1 + deg f − deg g.
        const int cofactor_degree = int(d) - 1 + int(field_degree) - int(deg_g);
        if (cofactor_degree < 0) continue;
        const Basis cofactor_basis(n, unsigned(cofactor_degree));
        std::vector<Polynomial> columns = rates;
        for (const auto& m : cofactor_basis.monomials) {
            Polynomial t = product(Polynomial{{m, 1}}, g);
            for (auto& [e, v] : t) v = -v;
            columns.push_back(std::move(t));
        }
        // The F part of each solution (F, Λ).
        std::vector<Row> conditional;
        for (const auto& r : null_space(equations_of(columns), columns.size(), work)) {
            Row F_part;
            for (const auto& [j, v] : r)
                if (j < rates.size()) F_part.emplace_back(j, v);
            if (!F_part.empty()) conditional.push_back(std::move(F_part));
        }
        // Trivial here: the known algebra, the unconditional integrals, and every multiple
        // g·m, which vanishes on the level set.
        std::vector<Row> trivial_here = trivial;
        trivial_here.insert(trivial_here.end(), integrals.begin(), integrals.end());
        for (const auto& m : monomials_up_to(n, int(d) - int(deg_g)))
            trivial_here.push_back(F_basis.row_of(product(Polynomial{{m, 1}}, g)));
        for (const auto& r : complement(conditional, trivial_here, work)) {
            const Polynomial F = primitive(F_basis.polynomial_of(r));
            const auto cofactor = exact_quotient(rate_of(F, field), g);
            if (!cofactor) throw std::logic_error("integral search: a conditional integral's rate is not a multiple of " + c.name);
            FoundIntegral f;
            f.value = expression_of(F, input.state);
            f.degree = degree_of(F);
            f.conditional = true;
            f.condition_name = "holds on " + c.name + " = " + level_text(c.level);
            f.cofactor = expression_of(*cofactor, input.state);
            confirm(f.value, f.cofactor, c.value - c.level, input);
            found.push_back(std::move(f));
        }
    }
    if (work_spent) *work_spent = work.spent();
    return found;
}

std::optional<GiNaC::numeric> rational_from_decimal(double v, unsigned max_significant_digits) {
    if (!std::isfinite(v)) return std::nullopt;
    if (v == 0) return GiNaC::numeric(0);
    // The shortest "%.{p-1}e" that reads back as v: the decimal the scene's author wrote.
    char text[64];
    for (unsigned p = 1; p <= std::min(max_significant_digits, 17u); ++p) {
        std::snprintf(text, sizeof text, "%.*e", int(p) - 1, v);
        if (std::strtod(text, nullptr) != v) continue;
        const std::string s(text);
        const std::size_t e_at = s.find('e');
        std::string digits;
        for (std::size_t i = 0; i < e_at; ++i)
            if (std::isdigit(static_cast<unsigned char>(s[i]))) digits += s[i];
        const long exponent = std::strtol(s.c_str() + e_at + 1, nullptr, 10) - long(p - 1);
        GiNaC::numeric value(std::strtoll(digits.c_str(), nullptr, 10));
        value *= GiNaC::numeric(10).power(exponent);
        return v < 0 ? -value : value;
    }
    return std::nullopt;
}

}  // namespace eomc::mechanics::rigid
