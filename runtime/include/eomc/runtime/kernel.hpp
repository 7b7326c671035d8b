#pragma once

// The contract of a generated kernel (templates/kernel.hpp.in), as C++20 concepts: one base
// concept for what every consumer needs, and one per optional part, which the emitter prints
// only for the kernels that have it. The loader's C adapter (templates/kernel_adapter.cpp),
// the bench driver (templates/bench_driver.cpp) and the compile check of tests/codegen test
// against these, so a kernel that drifts from its template fails to compile where it is used.
//
// Every function of a kernel is a static member template over the scalar S, called as
// f(t, x, out, p) with x and out arrays of S and p the kernel's Parameters. The concepts take S
// as a parameter (double by default) because consumers instantiate kernels for double, long
// double and float128 alike.

#include <array>
#include <concepts>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace eomc::runtime {

namespace kernel_detail {

// An array of exactly n elements of T (the kernel's name and value tables).
template <class A, class T, std::size_t n>
concept array_of = std::same_as<std::remove_cvref_t<A>, std::array<T, n>>;

// P{v[0], …, v[n−1]} from doubles compiles: no member narrows a double (an int or a float would).
template <class P, std::size_t... I>
constexpr bool brace_initialisable_from_doubles(std::index_sequence<I...>) {
  return requires(const std::array<double, sizeof...(I)>& v) { P{v[I]...}; };
}

}  // namespace kernel_detail

// The base: sizes, names, initial state, the Parameters aggregate (its defaults are the
// scene's), the rates ẋ = rhs(t, x) and the invariants. Hand-written kernels in this shape
// (tests/bench/driver) satisfy it too.
template <class K, class S = double>
concept Kernel = std::default_initializable<typename K::Parameters> &&
                 requires(S t, const S* x, S* out, const typename K::Parameters& p) {
                   { K::n_state } -> std::convertible_to<int>;
                   { K::n_coordinates } -> std::convertible_to<int>;
                   { K::n_parameters } -> std::convertible_to<int>;
                   { K::n_invariants } -> std::convertible_to<int>;
                   { K::scene_name } -> std::convertible_to<const char*>;
                   requires kernel_detail::array_of<decltype(K::state_names), const char*, std::size_t(K::n_state)>;
                   requires kernel_detail::array_of<decltype(K::parameter_names), const char*,
                                                    std::size_t(K::n_parameters)>;
                   requires kernel_detail::array_of<decltype(K::invariant_names), const char*,
                                                    std::size_t(K::n_invariants)>;
                   requires kernel_detail::array_of<decltype(K::initial_state), double, std::size_t(K::n_state)>;
                   K::template rhs<S>(t, x, out, p);
                   K::template invariants<S>(t, x, out, p);
                 };

// Quantities written beside the state (a free carrier's reactions, an orbit's Cartesian
// position in an element formulation), n_outputs of them in output_names order.
template <class K, class S = double>
concept KernelWithOutputs = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_outputs } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::output_names), const char*, std::size_t(K::n_outputs)>;
  K::template outputs<S>(t, x, out, p);
};

// ∂ẋ/∂x, row-major n_state × n_state: what the variational equations and implicit methods need.
template <class K, class S = double>
concept KernelWithJacobian = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  K::template jacobian<S>(t, x, out, p);
};

// The mechanical form M(t, x) u̇ = f(t, x) of the velocity block x[velocity_offset ..
// velocity_offset + n_velocities).
template <class K, class S = double>
concept KernelWithMassMatrix = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::velocity_offset } -> std::convertible_to<int>;
  { K::n_velocities } -> std::convertible_to<int>;
  K::template mass_matrix<S>(t, x, out, p);
  K::template forcing<S>(t, x, out, p);
};

// Everything templates/kernel.hpp.in prints for every scene, the `separable` and `has_jacobian`
// flags included; jacobian() is there exactly when has_jacobian says so (it is generated on
// request: eomc generate --jacobian).
template <class K, class S = double>
concept GeneratedKernel = KernelWithOutputs<K, S> && KernelWithMassMatrix<K, S> &&
                          requires {
                            { K::separable } -> std::convertible_to<bool>;
                            { K::has_jacobian } -> std::convertible_to<bool>;
                          } && (KernelWithJacobian<K, S> == bool(K::has_jacobian));

// Parameters travel by position (a C interface, a command line): then the struct must be an
// aggregate of exactly n_parameters doubles in parameter_names order, so that aggregate
// initialisation fills it by position and its bytes are an array of doubles. (Members that take
// a double without narrowing, n_parameters · 8 bytes in all: doubles.)
template <class K>
concept PositionalParameters =
    Kernel<K> && std::is_aggregate_v<typename K::Parameters> &&
    std::is_trivially_copyable_v<typename K::Parameters> && std::is_standard_layout_v<typename K::Parameters> &&
    (K::n_parameters == 0 || sizeof(typename K::Parameters) == std::size_t(K::n_parameters) * sizeof(double)) &&
    kernel_detail::brace_initialisable_from_doubles<typename K::Parameters>(
        std::make_index_sequence<std::size_t(K::n_parameters)>{});

// Optional parts.

// A separable system q̈ = a(t, q) (M constant, no velocity in the forces) also gives the
// acceleration alone, which the splitting methods step with.
template <class K, class S = double>
concept SeparableKernel = Kernel<K, S> && requires(S t, const S* q, S* a, const typename K::Parameters& p) {
  K::template acceleration<S>(t, q, a, p);
};

// A kernel that edits its state after every accepted step: project(t, x, p) puts a unit
// quaternion back on |e| = 1 or rectifies an Encke reference orbit. The drivers reach it
// through a system's project(t, x) (runtime::Projecting).
template <class K, class S = double>
concept ProjectingKernel = Kernel<K, S> && requires(S t, S* x, const typename K::Parameters& p) {
  K::template project<S>(t, x, p);
};

// A kernel whose mass matrix is singular on some set of states (gimbal lock of Euler angles):
// indicators s_k(t, x) of the sets s_k = 0, with their powers in det M; a simulation stops when
// the state comes close to one.
template <class K, class S = double>
concept SingularSetKernel = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_singular_sets } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::singular_set_names), const char*, std::size_t(K::n_singular_sets)>;
  requires kernel_detail::array_of<decltype(K::singular_set_orders), int, std::size_t(K::n_singular_sets)>;
  K::template singular_sets<S>(t, x, out, p);
};

// Event functions g_i(t, x) (scene [events]) with each one's direction (+1 up, -1 down, 0 both,
// as runtime::EventDirection) and whether it stops the integration.
template <class K, class S = double>
concept EventKernel = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_events } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::event_names), const char*, std::size_t(K::n_events)>;
  requires kernel_detail::array_of<decltype(K::event_directions), int, std::size_t(K::n_events)>;
  requires kernel_detail::array_of<decltype(K::event_terminal), bool, std::size_t(K::n_events)>;
  K::template events<S>(t, x, out, p);
};

// Bilateral constraint rows (generator/mechanics/constraints/rows.hpp): their names and one
// residual per row, f(q, t) for a holonomic row, φ(q, u, t) for a kinematic one. The multipliers
// are outputs (lambda_<row>); the projection, when a row asks for it, is the kernel's project().
template <class K, class S = double>
concept ConstrainedKernel = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_constraints } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::constraint_names), const char*, std::size_t(K::n_constraints)>;
  K::template constraint_residuals<S>(t, x, out, p);
};

// Programmed motion (generator/mechanics/control; Mei ch. 3): per program its name and its law
// (program_laws: configuration 1 or 0, α, β, κ; all gains 0 for the open loop) and
// program_residuals(): ω and ω̇ (configuration programs) or φ and 0, two per program.
template <class K, class S = double>
concept ProgramKernel = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_programs } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::program_names), const char*, std::size_t(K::n_programs)>;
  requires kernel_detail::array_of<decltype(K::program_laws), double, std::size_t(4 * K::n_programs)>;
  K::template program_residuals<S>(t, x, out, p);
};

// Unilateral constraints (Mei, Special Topics in Analytical Mechanics, ch. 6): per row a gap
// f(q, t) >= 0 or, where contact_kinematic, a kinematic row φ(q, u, t) >= 0 (§6.7); Newton's
// restitution coefficients from the parameters; gaps() writes f or φ, contact_jacobian() W
// (n_contacts × n_velocities, row-major) and contact_bias() the bias of f̈ (φ̇) = W u̇ + bias. With the
// mechanical form M u̇ = f (KernelWithMassMatrix) they make runtime::contact::ContactSystem.
template <class K, class S = double>
concept ContactKernel =
    KernelWithMassMatrix<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
      { K::n_contacts } -> std::convertible_to<int>;
      requires kernel_detail::array_of<decltype(K::contact_names), const char*, std::size_t(K::n_contacts)>;
      requires kernel_detail::array_of<decltype(K::contact_kinematic), bool, std::size_t(K::n_contacts)>;
      K::template restitutions<S>(p, out);
      K::template gaps<S>(t, x, out, p);
      K::template contact_jacobian<S>(t, x, out, p);
      K::template contact_bias<S>(t, x, out, p);
    };

// Contact kernels whose gaps move with t (a driven wall or table): contact_time_rates() writes
// w_α = ∂f_α/∂t per row, so that ḟ_α = W_α u + w_α (runtime::contact::ContactSystem::time_rates).
// A ContactKernel without it has fixed gaps, w = 0.
template <class K, class S = double>
concept MovingContactKernel = ContactKernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  K::template contact_time_rates<S>(t, x, out, p);
};

// Kernels with bilateral and unilateral rows (Mei §6.6): the bilateral rows as the contact drivers
// take them, always active with multipliers of free sign: residuals (f or φ), φ, W
// (n_constraints × n_velocities, row-major) and r of W u̇ = r, and which rows are holonomic.
template <class K, class S = double>
concept ContactConstrainedKernel =
    ContactKernel<K, S> && ConstrainedKernel<K, S> &&
    requires(S t, const S* x, S* out, S* phi, S* W, S* r, const typename K::Parameters& p) {
      requires kernel_detail::array_of<decltype(K::constraint_holonomic), bool, std::size_t(K::n_constraints)>;
      K::template constraint_rows<S>(t, x, out, phi, W, r, p);
    };

// Kernels generated with --variational: the rates of y = (x, Φ), n_variational = n_state +
// n_state², Φ row-major (runtime/variational.hpp).
template <class K, class S = double>
concept VariationalKernel = KernelWithJacobian<K, S> && requires(S t, const S* y, S* dydt, const typename K::Parameters& p) {
  requires K::n_variational == K::n_state + K::n_state * K::n_state;
  K::template variational_rhs<S>(t, y, dydt, p);
};

// Kernels of Newtonian scenes: the residuals of Santilli's conditions of variational
// self-adjointness (R.M. Santilli, Foundations of Theoretical Mechanics I, Springer 1978).
template <class K, class S = double>
concept SantilliKernel = Kernel<K, S> && requires(S t, const S* x, S* out, const typename K::Parameters& p) {
  { K::n_santilli_residuals } -> std::convertible_to<int>;
  requires kernel_detail::array_of<decltype(K::santilli_residual_names), const char*,
                                   std::size_t(K::n_santilli_residuals)>;
  K::template santilli_residuals<S>(t, x, out, p);
};

}  // namespace eomc::runtime
