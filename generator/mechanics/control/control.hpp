// Dynamics control (Mei, ch. 3): programmed motion realised by control forces. From the model's
// [[program]] rows: Ā, the bias and Erugin's law with Galiullin's gains, the control directions D,
// and whether D λ can realise the programs (Ā M⁻¹ D regular). Sources: Galiullin, Inverse Problems
// of Dynamics (Mir, 1984; Russian 1981), ch. 1–3; Erugin, PMM 16 (1952) 659–670; Udwadia & Kalaba,
// Analytical Dynamics: A New Approach (Cambridge, 1996), ch. 2 (redundant ideal programs).
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/control/rows.hpp"
#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// One row per program, in scene order, for a model given by its energies (M and f in `eqs`).
// Throws InputError at the program's control when it brings more controls than the programs need
// (λ not determined) and, for programs with a non-ideal control, when Ā M⁻¹ D is singular at every
// probe point (underactuated: no control in these directions realises the programs), naming the
// programs. Ideal programs that are dependent (Ā of deficient rank) are accepted: Udwadia–Kalaba.
// Creates no symbol (it runs on the way to the kernel).
std::vector<ProgramRow> program_rows(const model::Model& model, const Equations& eqs);

// Whether every program is ideal and Ā has deficient rank at every probe point: the kernel then
// takes the Udwadia–Kalaba acceleration q̈ = M⁻¹f + M^{-1/2}(Ā M^{-1/2})⁺(c − Ā M⁻¹ f).
bool redundant_ideal(const model::Model& model, const Equations& eqs);

// The realisation in closed form, for the report (creates symbols: after the kernel).
struct Realisation {
    std::size_t programs = 0, controls = 0, velocities = 0;
    GiNaC::matrix A, D, c;                // Ā (m × n), D (n × k), c (m × 1)
    bool redundant = false;               // ideal and dependent: Udwadia–Kalaba, no λ of its own
    std::optional<GiNaC::matrix> AMD;     // Ā M⁻¹ D, normalised
    std::optional<GiNaC::ex> determinant; // det Ā M⁻¹ D, normalised
    std::vector<GiNaC::ex> singular;      // the factors of det's numerator that vanish on some state
    std::optional<std::vector<GiNaC::ex>> lambda, Qc;  // λ = (Ā M⁻¹ D)⁻¹ (c − Ā M⁻¹ f), Q_c = D λ
    std::string why_not;                  // why the closed forms are absent
    bool realisable = true;               // det not identically zero
};

Realisation realise(const model::Model& model, const Equations& eqs);

// The eigenvalues of a closed-loop program's residual law (none for an open loop), whatever the
// mechanics: ω̈ + 2αω̇ + β²ω = 0 has −α ± √(α² − β²), complex −α ± i√(β² − α²) for α < β (one of
// the pair is given), φ̇ + κφ = 0 has −κ. The host judges them against the chosen integrator's
// stability region (host/simulate/program_stiffness.hpp).
std::vector<std::complex<double>> residual_eigenvalues(const model::Program& p);

}  // namespace eomc::mechanics
