// Jacobi's last multiplier of Lagrange's equations, Jacobi's count of integrals, and the sets
// where the mass matrix is singular (Mei, Special Topics in Analytical Mechanics, ch. 5;
// Whittaker, Analytical Dynamics, §§118–119).
//
// Written as the first-order system x = (q, q̇), ẋ = F = (q̇, M⁻¹f), Lagrange's equations of a
// Lagrangian L (no forces outside it) have the last multiplier μ = det(∂²L/∂q̇²) = det M:
//     ∂μ/∂t + div(μ F) = ∂μ/∂t + Σ_s q̇_s ∂μ/∂q_s + Σ_s ∂(adj(M) f)_s/∂q̇_s ≡ 0
// (μ M⁻¹ = adj M, so no division appears). A generalized force that depends on q̇ (a damping
// −c q̇) breaks the identity: then det M is reported as not a multiplier. Jacobi's theorem: an
// autonomous system of m equations with a last multiplier and m − 2 independent integrals free
// of t is integrable by quadratures (m − 1 integrals when F depends on t).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::rigid {

// det A by expansion along the first row, expanded; no symbol is created (GiNaC's own
// determinant and factor() make temporary symbols, which would shift the hash order of
// everything derived afterwards, and so the generated kernels).
GiNaC::ex expanded_determinant(const GiNaC::matrix& A);

// The sets where det M = 0, for a model given by its energies without a free carrier (empty
// otherwise, or when M is constant, or larger than 5 × 5). det M is expanded (also with
// sin² = 1 − cos² and cos² = 1 − sin²), the powers of each coordinate-dependent atom
// (a coordinate, sin(·), cos(·), …) common to all its terms are factored out, and each such
// factor that vanishes for some real state (a sine or cosine of a coordinate, or one that takes
// both signs over sampled states at the parameters' defaults) is a set, as is the remaining
// cofactor when it takes both signs. Creates no symbol: runs in derive(), on the way to the kernel.
std::vector<SingularSet> singular_sets(const model::Model& model, const Equations& eqs);

enum class MultiplierStatus {
    proven,          // ∂μ/∂t + div(μF) simplifies to zero
    not_multiplier,  // nonzero at a sampled state (e.g. a damping force)
    undecided,       // zero at every sampled state, but not simplified to zero
    not_applicable,  // a free carrier, constraint rows: F is not (q̇, M⁻¹f)
};

struct LastMultiplier {
    MultiplierStatus status = MultiplierStatus::not_applicable;
    GiNaC::ex mu;          // det M
    GiNaC::ex divergence;  // ∂μ/∂t + div(μF), as formed (not simplified)
    std::string reason;    // how it was decided, for the printer
};

// Creates symbols (simplification): for reports only, after the kernel.
LastMultiplier last_multiplier(const model::Model& model, const Equations& eqs);

struct JacobiCount {
    std::size_t equations = 0;             // 2n
    bool autonomous = true;                // M and f free of t
    std::vector<std::string> integrals;    // the proven invariants used (independent; free of t when autonomous)
    std::size_t needed = 0;                // 2n − 2 (autonomous) or 2n − 1
    std::size_t missing = 0;
    std::size_t cyclic = 0;                // proven cyclic momenta among the integrals
    std::size_t reduced_equations = 0;     // 2(n − cyclic), after Routh's reduction
    std::size_t reduced_needed = 0;
    std::size_t reduced_missing = 0;       // the integrals other than the momenta, against reduced_needed
    bool multiplier = false;               // a last multiplier is known (proven)
    bool integrable = false;               // multiplier and no integral missing (reduced or not)
};

JacobiCount jacobi_count(const model::Model& model, const Equations& eqs, const LastMultiplier& multiplier,
                         std::size_t proven_cyclic);

}  // namespace eomc::mechanics::rigid
