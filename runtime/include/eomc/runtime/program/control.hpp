#pragma once

// The controlled equations of a programmed motion in a generated kernel (generator/mechanics/
// control/rows.hpp; Mei ch. 3; Galiullin, Inverse Problems of Dynamics, 1981):
//   M u̇ = f + D λ,   Ā u̇ = c,
// with M symmetric positive definite, Ā m × n, D n × m. With Y = M⁻¹ D and z = M⁻¹ f,
//   λ = (Ā Y)⁻¹ (c − Ā z),   u̇ = z + Y λ,
// realisable where Ā M⁻¹ D is regular. For ideal programs whose rows are dependent (Ā of deficient
// rank) the acceleration is Udwadia and Kalaba's (Analytical Dynamics: A New Approach, Cambridge
// 1996, ch. 2): the minimiser of Gauss's (u̇ − z)ᵀ M (u̇ − z) subject to Ā u̇ = c, here through
// M = L Lᵀ, u̇ = z + L⁻ᵀ (Ā L⁻ᵀ)⁺ (c − Ā z), which is the book's M^{−1/2} form with L in place of
// the symmetric root (the minimiser does not depend on the factor).
//
// Kernels whose M fits the generator's straight-line solve reduce the programs themselves and use
// reduced_control.hpp instead; this Eigen path serves dependent ideal programs and larger M.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/QR>

namespace eomc::runtime::program {

template <class S>
using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

// u̇, λ and the generalized control force Q_c = D λ.
template <class S>
void control_solve(const Matrix<S>& M, const Vector<S>& f, const Matrix<S>& A, const Matrix<S>& D, const Vector<S>& c,
                   Vector<S>& udot, Vector<S>& lambda, Vector<S>& Qc) {
  const Eigen::LDLT<Matrix<S>> ldlt(M);
  const Matrix<S> Y = ldlt.solve(D);
  const Vector<S> z = ldlt.solve(f);
  lambda = (A * Y).fullPivLu().solve(c - A * z);
  udot = z + Y * lambda;
  Qc = D * lambda;
}

// det(Ā M⁻¹ D): zero where no control in these directions realises the programs.
template <class S>
S control_determinant(const Matrix<S>& M, const Matrix<S>& A, const Matrix<S>& D) {
  return (A * M.ldlt().solve(D)).fullPivLu().determinant();
}

// Udwadia–Kalaba for dependent ideal programs (D = Āᵀ): u̇, Q_c = M(u̇ − z), and the minimum-norm
// λ with Āᵀ λ = Q_c.
template <class S>
void udwadia_kalaba_solve(const Matrix<S>& M, const Vector<S>& f, const Matrix<S>& A, const Vector<S>& c,
                          Vector<S>& udot, Vector<S>& lambda, Vector<S>& Qc) {
  const Eigen::LLT<Matrix<S>> llt(M);
  const Vector<S> z = llt.solve(f);
  // B = Ā L⁻ᵀ, i.e. Bᵀ = L⁻¹ Āᵀ.
  const Matrix<S> Bt = llt.matrixL().solve(A.transpose());
  const Matrix<S> B = Bt.transpose();
  const Vector<S> x = B.completeOrthogonalDecomposition().solve(c - A * z);  // (Ā L⁻ᵀ)⁺ (c − Ā z)
  const Vector<S> correction = llt.matrixU().solve(x);                       // L⁻ᵀ x
  udot = z + correction;
  Qc = M * correction;
  const Matrix<S> At = A.transpose();
  lambda = At.completeOrthogonalDecomposition().solve(Qc);
}

}  // namespace eomc::runtime::program
