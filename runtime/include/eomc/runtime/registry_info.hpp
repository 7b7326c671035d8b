#pragma once

// The catalogue of the runtime's integrators as plain descriptors: one entry per method, with the
// name scenes and the command line use, its kind, order and traits, and a one-line description.
// No stepper is included here, so that a reader of scenes or flags can validate and list methods
// without compiling them; registry.hpp pairs each descriptor with its stepper type.
//
// Everything that lists, validates or judges methods by their traits (scene validation, `eomc
// simulate`, `eomc bench`, the ensembles' batches, the stiffness hints, --help) reads this table,
// so a new method is one entry here and one in registry.hpp.

#include <array>
#include <concepts>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace eomc::runtime {

enum class IntegratorKind {
  fixed,                 // explicit, fixed step
  adaptive,              // embedded pair under step-size control (tolerances, no step)
  implicit,              // implicit Runge-Kutta, fixed step
  symplectic_splitting,  // composition of kicks and drifts, fixed step, separable kernels only
};

struct IntegratorInfo {
  std::string_view name;  // as in scenes ([simulate] integrator) and on the command line
  IntegratorKind kind = IntegratorKind::fixed;
  int order = 0;
  bool needs_separable = false;         // takes the acceleration a(t, q) of a separable kernel, not f(t, x)
  bool dense_output = false;            // a continuous solution over each step (event location, output times)
  bool symplectic = false;              // preserves the symplectic form (long-run energy behaviour)
  bool compensated_by_default = false;  // compensated summation of the update on unless the scene says
  std::string_view description;
  // Implicit, with a Newton iteration on the system's Jacobian (sys.jacobian(t, x, J) where the
  // system has one, finite differences otherwise): drivers hand it a system with the kernel's Jacobian.
  bool uses_jacobian = false;
  // Runs lock-step SIMD batches of systems (batch/lock_step.hpp): one step size for the batch.
  bool batch = false;
  // Where the negative real axis leaves the stability region of an explicit method, |h λ| at the
  // boundary (0: unbounded or not applicable). Fixes the step an explicit method can take on a
  // decaying mode λ: the stiffness hints and the programs' stiffness warnings read it.
  double real_stability_boundary = 0.0;
  // An explicit fixed-step method's stability function R(z) = Σ c_k z^k (the factor of a step on
  // ẏ = λy, z = hλ), its coefficients from z⁰ up; all zero where not given. The programs'
  // stiffness warnings test |R(hλ)| ≤ 1 with it.
  std::array<double, 9> stability_polynomial{};

  // Takes a step size (fixed-step methods) rather than tolerances.
  constexpr bool fixed_step() const { return kind != IntegratorKind::adaptive; }
  // Solves an implicit stage system each step (Gauss-Legendre, Radau IIA).
  constexpr bool implicit() const { return kind == IntegratorKind::implicit || uses_jacobian; }
  // An explicit method whose step stability bounds on a stiff system (an explicit Runge-Kutta pair
  // or rk4): real_stability_boundary says where.
  constexpr bool stability_limited() const { return real_stability_boundary > 0.0; }
  // Whether stability_polynomial is given.
  constexpr bool has_stability_polynomial() const { return stability_polynomial[0] != 0.0; }
};

// The catalogue, in the order listings show it. The real stability boundaries: RK4's interval
// [−2.785, 0] (the real root of |1 + z + z²/2 + z³/6 + z⁴/24| = 1); DOPRI5 ≈ 3.3 and DOP853 ≈ 6.1,
// the values Hairer's dopri5.f and dop853.f use for their stiffness detection (E. Hairer,
// G. Wanner, Solving Ordinary Differential Equations II, Sect. IV.2).
inline constexpr std::array<IntegratorInfo, 10> integrator_infos{{
    {.name = "rk4",
     .kind = IntegratorKind::fixed,
     .order = 4,
     .description = "classical Runge-Kutta, order 4, fixed step (Kutta 1901)",
     .batch = true,
     .real_stability_boundary = 2.785,
     .stability_polynomial = {1.0, 1.0, 1.0 / 2, 1.0 / 6, 1.0 / 24}},
    {.name = "dopri5",
     .kind = IntegratorKind::adaptive,
     .order = 5,
     .dense_output = true,
     .description = "Dormand-Prince 5(4), adaptive, dense output (Dormand & Prince 1980)",
     .batch = true,
     .real_stability_boundary = 3.3},
    {.name = "dop853",
     .kind = IntegratorKind::adaptive,
     .order = 8,
     .dense_output = true,
     .description = "Dormand-Prince 8(5,3), adaptive, dense output (Prince & Dormand 1981, Hairer's DOP853)",
     .real_stability_boundary = 6.1},
    {.name = "radau5",
     .kind = IntegratorKind::adaptive,
     .order = 5,
     .dense_output = true,
     .description = "Radau IIA, 3 stages, order 5, implicit, L-stable, adaptive, dense output, for stiff systems "
                    "(Hairer-Wanner RADAU5)",
     .uses_jacobian = true},
    {.name = "gl4",
     .kind = IntegratorKind::implicit,
     .order = 4,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Gauss-Legendre, 2 stages, order 4, implicit, symplectic, fixed step"},
    {.name = "gl6",
     .kind = IntegratorKind::implicit,
     .order = 6,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Gauss-Legendre, 3 stages, order 6, implicit, symplectic, fixed step"},
    {.name = "gl8",
     .kind = IntegratorKind::implicit,
     .order = 8,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Gauss-Legendre, 4 stages, order 8, implicit, symplectic, fixed step"},
    {.name = "verlet",
     .kind = IntegratorKind::symplectic_splitting,
     .order = 2,
     .needs_separable = true,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Stormer-Verlet (kick-drift-kick), order 2, separable kernels"},
    {.name = "yoshida6",
     .kind = IntegratorKind::symplectic_splitting,
     .order = 6,
     .needs_separable = true,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Yoshida's 7-stage composition of Verlet, order 6, separable kernels (Yoshida 1990)"},
    {.name = "kahanli8",
     .kind = IntegratorKind::symplectic_splitting,
     .order = 8,
     .needs_separable = true,
     .symplectic = true,
     .compensated_by_default = true,
     .description = "Kahan-Li 15-stage composition of Verlet, order 8, separable kernels (Kahan & Li 1997)"},
}};

// What a scene or a request runs when it names no integrator.
inline constexpr std::string_view default_integrator = "dopri5";

inline constexpr std::array<std::string_view, integrator_infos.size()> integrator_names = [] {
  std::array<std::string_view, integrator_infos.size()> names{};
  for (std::size_t i = 0; i < names.size(); ++i) names[i] = integrator_infos[i].name;
  return names;
}();

// The position of `name` in the catalogue, or its size. (Constant expressions go by index: under
// the sanitizers GCC does not fold a comparison of pointers into the table.)
constexpr std::size_t integrator_index(std::string_view name) {
  std::size_t i = 0;
  while (i < integrator_infos.size() && integrator_infos[i].name != name) ++i;
  return i;
}

// The descriptor of `name`, or nullptr.
constexpr const IntegratorInfo* find_integrator(std::string_view name) {
  const std::size_t i = integrator_index(name);
  return i < integrator_infos.size() ? &integrator_infos[i] : nullptr;
}

constexpr bool is_integrator(std::string_view name) { return integrator_index(name) < integrator_infos.size(); }
static_assert(is_integrator(default_integrator));

// The names of the entries `keep` accepts, joined by `separator` and the last two by
// `last_separator` ("gl4, gl6 or gl8"; the separator when empty), for messages and --help.
template <std::predicate<const IntegratorInfo&> Keep>
std::string integrator_list(Keep keep, std::string_view separator = ", ", std::string_view last_separator = {}) {
  std::vector<std::string_view> names;
  for (const IntegratorInfo& info : integrator_infos)
    if (keep(info)) names.push_back(info.name);
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() && !last_separator.empty() ? last_separator : separator;
    out += names[i];
  }
  return out;
}

// Every name, joined by `separator`.
inline std::string integrator_list(std::string_view separator = ", ") {
  return integrator_list([](const IntegratorInfo&) { return true; }, separator);
}

// The names of the entries `keep` accepts, for defaults and option checks.
template <std::predicate<const IntegratorInfo&> Keep>
std::vector<std::string> integrator_names_where(Keep keep) {
  std::vector<std::string> out;
  for (const IntegratorInfo& info : integrator_infos)
    if (keep(info)) out.emplace_back(info.name);
  return out;
}

}  // namespace eomc::runtime
