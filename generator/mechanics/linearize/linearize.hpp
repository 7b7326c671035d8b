// Linearisation of the equations of motion about an operating point — an equilibrium or a steady
// motion — with the bilateral [[constraint]] rows (holonomic and kinematic) eliminated to a minimal
// set of independent coordinates and speeds, after Peterson, Gede and Hubbard, "Symbolic
// linearization of equations of motion of constrained multibody systems", Multibody Syst. Dyn. 33
// (2015) 143–161 (PGH below).
//
// The system is q̇ = u, M(q) u̇ − Wᵀλ = f(q, u), the holonomic rows f_h(q) = 0 and the velocity rows
// φ(q, u) = W u + b = 0 (ḟ_h for a holonomic row). Its Jacobians are built symbolically, once per
// scene; at an operating point (q₀, u₀) with its u̇₀, λ₀ they are evaluated and
//   δq = C₀ δq_i,  δu = C₁ δq_i + C₂ δu_i                                   (PGH eqs. 20–27)
// with C₀ = (I − P_qd (f_hq P_qd)⁻¹ f_hq) P_qi, C₁ = −P_ud (φ_u P_ud)⁻¹ φ_q C₀,
// C₂ = (I − P_ud (φ_u P_ud)⁻¹ φ_u) P_ui; the accelerations and multipliers follow (δu̇, δλ) from the
// linearised dynamic and acceleration-level rows together, so that
//   d/dt (δq_i, δu_i) = A (δq_i, δu_i),   A = Pᵀ [[0, I], [∂u̇/∂q, ∂u̇/∂u]] [[C₀, 0], [C₁, C₂]],
// P picking the independent rows. The dependent coordinates and speeds are chosen by column-pivoted
// QR of f_hq and φ_u at the point (the best conditioned blocks to invert).
#pragma once

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

enum class OperatingPointKind {
    equilibrium,  // the rest state nearest the initial configuration (Newton on f + Wᵀλ = 0, rows)
    initial,      // the initial state as given: an equilibrium, or a steady motion
};

enum class LinearStability { asymptotically_stable, stable_linear, unstable };

// "asymptotically stable" | "stable in the linear approximation" | "unstable".
const char* stability_name(LinearStability s);

struct Linearization {
    std::vector<double> q, u;           // the operating point: every coordinate and rate
    std::vector<double> accelerations;  // u̇ there (zero at a steady point, to round-off)
    std::vector<double> multipliers;    // λ there, one per row
    std::vector<std::size_t> independent_coordinates, dependent_coordinates;  // model indices
    std::vector<std::size_t> independent_speeds, dependent_speeds;
    std::vector<std::string> state;  // the names of A's rows: the independent q, then the independent q_dot
    Eigen::MatrixXd A;
    // Independent coordinates whose column of A is zero once the rows of those found before are
    // set aside (cyclic in the linear equations: x, y and the heading of a sleigh).
    std::vector<std::size_t> ignorable;
    std::vector<std::complex<double>> eigenvalues;  // of A, by decreasing real part, then imaginary part
    Eigen::MatrixXcd modes;                         // column j: the eigenvector of eigenvalues[j], over `state`
    LinearStability verdict = LinearStability::unstable;
    std::string reason;      // why the verdict (which eigenvalues decided it)
    double tolerance = 0.0;  // |Re λ| at most this is on the imaginary axis
};

// The scene's equations, their Jacobians built once. Throws InputError at the scene for what it does
// not linearise: an orbit, a free carrier, a rigid body outside Euler angles, [[unilateral]] rows,
// [[program]] rows, equations that depend on t explicitly.
class Linearizer {
public:
    Linearizer(const model::Model& model, const Equations& equations);

    // Parameters in model order; q, u the initial state (every coordinate, every rate). Throws
    // InputError, at `where`, when the point is not steady (accelerations or rows' residuals beyond
    // round-off, or a moving coordinate entering the equations) or when no equilibrium is found.
    Linearization linearize(const std::vector<double>& parameters, OperatingPointKind about, std::vector<double> q,
                            std::vector<double> u, const SourcePos& where) const;

    std::size_t coordinates() const { return n_; }
    std::size_t holonomic_rows() const { return l_; }
    std::size_t velocity_rows() const { return m_; }

private:
    struct Point;
    Point evaluate_at(const std::vector<double>& parameters, const std::vector<double>& q, const std::vector<double>& u,
                      const std::vector<double>& udot, const std::vector<double>& lambda) const;
    void find_equilibrium(const std::vector<double>& parameters, std::vector<double>& q, const SourcePos& where) const;
    void check_steady(const Point& at, const std::vector<double>& q, const std::vector<double>& u, Linearization& out,
                      const SourcePos& where) const;

    const model::Model& model_;
    std::size_t n_ = 0, l_ = 0, m_ = 0;
    std::vector<GiNaC::ex> mass_, forcing_, W_, bias_;          // M (n×n), f (n), W (m×n), b̂ (m) of W u̇ + b̂
    std::vector<GiNaC::ex> dynamic_q_, dynamic_u_;              // ∂/∂q, ∂/∂u of (M u̇ − f − Wᵀλ; W u̇ + b̂)
    std::vector<GiNaC::ex> holonomic_, holonomic_q_;            // f_h (l), ∂f_h/∂q (l×n)
    std::vector<GiNaC::ex> velocity_, velocity_q_;              // φ (m), ∂φ/∂q (m×n); ∂φ/∂u = W
    std::vector<GiNaC::symbol> lambda_;
    std::vector<bool> enters_;  // per coordinate: it appears in M, f, W, b̂, f_h or φ
};

// Eigenvalues, modes, ignorable coordinates and the verdict of out.A, whose leading rows are those of
// out.independent_coordinates (filled by linearize; exposed for tests of the classification on
// matrices of known spectrum).
void classify_linearization(Linearization& out);

}  // namespace eomc::mechanics
