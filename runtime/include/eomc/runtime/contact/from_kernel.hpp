#pragma once

// A generated kernel's contact blocks as the ContactSystem both contact drivers take (system.hpp):
// written once, for a kernel compiled into the user's program (KernelContactBlocks below) and for
// one the host loads at run time (which provides the same blocks over its C interface).
//
// The kernel's state is x = (q, u) with u = q̇ (the drivers assume it): each callable puts (q, u)
// into x, u = 0 where the block reads positions only (its value cannot depend on u), and copies the
// kernel's row-major arrays into the drivers' Eigen matrices.

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <memory>
#include <vector>

#include "eomc/runtime/contact/system.hpp"
#include "eomc/runtime/kernel.hpp"

namespace eomc::runtime::contact {

// What contact_system() reads of a kernel, over arrays of S at the state x = (q, u):
//   dof()                        n, the coordinates (and velocities);
//   contact_count(), kinematic(α), restitutions(e)   the unilateral rows;
//   mass_matrix, forcing, gaps, contact_jacobian (m × n), contact_bias   (t, x, out);
//   moving(), contact_time_rates(t, x, w)             ∂g/∂t of moving gaps (moving() false: none);
//   bilateral_count(), bilateral_holonomic(i), constraint_rows(t, x, f, phi, C, r)   the bilateral rows.
template <class B, class S>
concept ContactBlocks = requires(const B& b, S t, const S* x, S* out, std::size_t i) {
  { b.dof() } -> std::convertible_to<int>;
  { b.contact_count() } -> std::convertible_to<std::size_t>;
  { b.kinematic(i) } -> std::convertible_to<bool>;
  b.restitutions(out);
  b.mass_matrix(t, x, out);
  b.forcing(t, x, out);
  b.gaps(t, x, out);
  b.contact_jacobian(t, x, out);
  b.contact_bias(t, x, out);
  { b.moving() } -> std::convertible_to<bool>;
  b.contact_time_rates(t, x, out);
  { b.bilateral_count() } -> std::convertible_to<std::size_t>;
  { b.bilateral_holonomic(i) } -> std::convertible_to<bool>;
  b.constraint_rows(t, x, out, out, out, out);
};

// A compiled-in kernel K (ContactKernel; MovingContactKernel and ContactConstrainedKernel where it
// is one) with its parameters, as ContactBlocks. Holds a reference to the parameters.
template <class K, class S = double>
  requires ContactKernel<K, S>
struct KernelContactBlocks {
  const typename K::Parameters& parameters;

  int dof() const { return K::n_coordinates; }
  std::size_t contact_count() const { return std::size_t(K::n_contacts); }
  bool kinematic(std::size_t a) const { return K::contact_kinematic[a]; }
  void restitutions(S* e) const { K::template restitutions<S>(parameters, e); }
  void mass_matrix(S t, const S* x, S* out) const { K::template mass_matrix<S>(t, x, out, parameters); }
  void forcing(S t, const S* x, S* out) const { K::template forcing<S>(t, x, out, parameters); }
  void gaps(S t, const S* x, S* out) const { K::template gaps<S>(t, x, out, parameters); }
  void contact_jacobian(S t, const S* x, S* out) const { K::template contact_jacobian<S>(t, x, out, parameters); }
  void contact_bias(S t, const S* x, S* out) const { K::template contact_bias<S>(t, x, out, parameters); }
  bool moving() const { return MovingContactKernel<K, S>; }
  void contact_time_rates(S t, const S* x, S* out) const {
    if constexpr (MovingContactKernel<K, S>) K::template contact_time_rates<S>(t, x, out, parameters);
  }
  std::size_t bilateral_count() const {
    if constexpr (ContactConstrainedKernel<K, S>) return std::size_t(K::n_constraints);
    else return 0;
  }
  bool bilateral_holonomic(std::size_t i) const {
    if constexpr (ContactConstrainedKernel<K, S>) return K::constraint_holonomic[i];
    else return (void)i, false;
  }
  void constraint_rows(S t, const S* x, S* f, S* phi, S* C, S* r) const {
    if constexpr (ContactConstrainedKernel<K, S>) K::template constraint_rows<S>(t, x, f, phi, C, r, parameters);
  }
};

namespace detail {

// The blocks and the scratch the callables share: the kernel's state and its row-major arrays.
template <class S, class B>
struct KernelContactScratch {
  B blocks;
  int n;
  std::size_t m, k;
  std::vector<S> x, buffer;

  KernelContactScratch(const B& b)
      : blocks(b), n(b.dof()), m(b.contact_count()), k(b.bilateral_count()), x(2 * std::size_t(n), S(0)),
        buffer(std::max<std::size_t>({m, k, 1}) * std::size_t(n) + std::size_t(n) * std::size_t(n)) {}

  // x = (q, u), or (q, 0) for a block of the positions alone.
  const S* put(const Vector<S>& q, const Vector<S>* u) {
    for (int j = 0; j < n; ++j) {
      x[std::size_t(j)] = q[j];
      x[std::size_t(n + j)] = u ? (*u)[j] : S(0);
    }
    return x.data();
  }
  // The first rows × n entries of the buffer, row-major, into out.
  void copy_rows(Matrix<S>& out, std::size_t rows) const {
    for (std::size_t i = 0; i < rows; ++i)
      for (int j = 0; j < n; ++j) out(Eigen::Index(i), j) = buffer[i * std::size_t(n) + std::size_t(j)];
  }
};

}  // namespace detail

// The ContactSystem of a kernel's blocks. The system holds a copy of `blocks` (a view: it must not
// outlive what the view refers to, such as the kernel's parameters) and its own scratch, so one
// system serves one run at a time.
template <class S, class B>
  requires ContactBlocks<B, S>
ContactSystem<S> contact_system(const B& blocks) {
  auto scratch = std::make_shared<detail::KernelContactScratch<S, B>>(blocks);
  ContactSystem<S> sys;
  sys.dof = scratch->n;
  std::vector<S> e(std::max<std::size_t>(scratch->m, 1));
  blocks.restitutions(e.data());
  for (std::size_t a = 0; a < scratch->m; ++a)
    sys.contacts.push_back({e[a], blocks.kinematic(a) ? GapLevel::velocity : GapLevel::position});
  sys.mass = [scratch](S t, const Vector<S>& q, Matrix<S>& M) {
    auto& s = *scratch;
    s.blocks.mass_matrix(t, s.put(q, nullptr), s.buffer.data());
    s.copy_rows(M, std::size_t(s.n));
  };
  sys.force = [scratch](S t, const Vector<S>& q, const Vector<S>& u, Vector<S>& f) {
    scratch->blocks.forcing(t, scratch->put(q, &u), f.data());
  };
  sys.gaps = [scratch](S t, const Vector<S>& q, const Vector<S>& u, Vector<S>& g) {
    scratch->blocks.gaps(t, scratch->put(q, &u), g.data());
  };
  sys.rows = [scratch](S t, const Vector<S>& q, const Vector<S>& u, Matrix<S>& W, Vector<S>& b) {
    auto& s = *scratch;
    const S* x = s.put(q, &u);
    s.blocks.contact_jacobian(t, x, s.buffer.data());
    s.copy_rows(W, s.m);
    s.blocks.contact_bias(t, x, b.data());
  };
  // Moving gaps: ġ = W u + w, w = ∂g/∂t (fixed gaps leave it out: w = 0).
  if (blocks.moving())
    sys.time_rates = [scratch](S t, const Vector<S>& q, Vector<S>& w) {
      scratch->blocks.contact_time_rates(t, scratch->put(q, nullptr), w.data());
    };
  for (std::size_t i = 0; i < scratch->k; ++i) sys.bilateral_holonomic.push_back(blocks.bilateral_holonomic(i));
  if (scratch->k > 0)
    sys.bilateral = [scratch](S t, const Vector<S>& q, const Vector<S>& u, Vector<S>& f, Vector<S>& phi, Matrix<S>& C,
                              Vector<S>& r) {
      auto& s = *scratch;
      const Eigen::Index k = Eigen::Index(s.k);
      f.resize(k);
      phi.resize(k);
      r.resize(k);
      C.resize(k, s.n);
      s.blocks.constraint_rows(t, s.put(q, &u), f.data(), phi.data(), s.buffer.data(), r.data());
      s.copy_rows(C, s.k);
    };
  return sys;
}

}  // namespace eomc::runtime::contact
