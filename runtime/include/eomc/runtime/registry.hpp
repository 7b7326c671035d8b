#pragma once

// The catalogue of the runtime's integrators: one entry per method, with the name scenes and the
// command line use, its kind, order and traits, a one-line description, and the stepper type.
// Everything that lists, validates or dispatches on method names (scene validation, `eomc
// simulate`, `eomc bench`, --help) derives from this list, so a new method is added here once.
//
// Adding an integrator: its stepper header under stepper/, one entry struct below, and its name in
// IntegratorList; tests/runtime/registry.cpp then checks that it dispatches and that the declared
// order is the stepper's.

#include <array>
#include <concepts>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "eomc/runtime/stepper/gauss_legendre.hpp"
#include "eomc/runtime/stepper/radau5.hpp"
#include "eomc/runtime/stepper/rk4.hpp"
#include "eomc/runtime/stepper/splitting.hpp"

namespace eomc::runtime {

enum class IntegratorKind {
  fixed,                 // explicit, fixed step
  adaptive,              // embedded pair under step-size control (tolerances, no step)
  implicit,              // implicit Runge-Kutta, fixed step
  symplectic_splitting,  // composition of kicks and drifts, fixed step, separable kernels only
};

struct IntegratorInfo {
  std::string_view name;  // as in scenes ([simulate] integrator) and on the command line
  IntegratorKind kind;
  int order;
  bool needs_separable;         // takes the acceleration a(t, q) of a separable kernel, not f(t, x)
  bool dense_output;            // a continuous solution over each step (event location, output times)
  bool symplectic;              // preserves the symplectic form (long-run energy behaviour)
  bool compensated_by_default;  // compensated summation of the update on unless the scene says
  std::string_view description;
  // Implicit, with a Newton iteration on the system's Jacobian (sys.jacobian(t, x, J) where the
  // system has one, finite differences otherwise): drivers hand it a system with the kernel's Jacobian.
  bool uses_jacobian = false;

  // Takes a step size (fixed-step methods) rather than tolerances.
  constexpr bool fixed_step() const { return kind != IntegratorKind::adaptive; }
};

namespace integrators {

// One struct per method: `stepper<S>` is its runtime type, `info` its descriptor.
struct rk4 {
  template <class S>
  using stepper = Rk4<S>;
  static constexpr IntegratorInfo info{
      "rk4", IntegratorKind::fixed, 4, false, false, false, false,
      "classical Runge-Kutta, order 4, fixed step (Kutta 1901)"};
};
struct dopri5 {
  template <class S>
  using stepper = Dopri5<S>;
  static constexpr IntegratorInfo info{
      "dopri5", IntegratorKind::adaptive, 5, false, true, false, false,
      "Dormand-Prince 5(4), adaptive, dense output (Dormand & Prince 1980)"};
};
struct dop853 {
  template <class S>
  using stepper = Dop853<S>;
  static constexpr IntegratorInfo info{
      "dop853", IntegratorKind::adaptive, 8, false, true, false, false,
      "Dormand-Prince 8(5,3), adaptive, dense output (Prince & Dormand 1981, Hairer's DOP853)"};
};
struct radau5 {
  template <class S>
  using stepper = Radau5<S>;
  static constexpr IntegratorInfo info{
      "radau5", IntegratorKind::adaptive, 5, false, true, false, false,
      "Radau IIA, 3 stages, order 5, implicit, L-stable, adaptive, dense output, for stiff systems (Hairer-Wanner RADAU5)",
      true};
};
struct gl4 {
  template <class S>
  using stepper = Gl4<S>;
  static constexpr IntegratorInfo info{
      "gl4", IntegratorKind::implicit, 4, false, false, true, true,
      "Gauss-Legendre, 2 stages, order 4, implicit, symplectic, fixed step"};
};
struct gl6 {
  template <class S>
  using stepper = Gl6<S>;
  static constexpr IntegratorInfo info{
      "gl6", IntegratorKind::implicit, 6, false, false, true, true,
      "Gauss-Legendre, 3 stages, order 6, implicit, symplectic, fixed step"};
};
struct gl8 {
  template <class S>
  using stepper = Gl8<S>;
  static constexpr IntegratorInfo info{
      "gl8", IntegratorKind::implicit, 8, false, false, true, true,
      "Gauss-Legendre, 4 stages, order 8, implicit, symplectic, fixed step"};
};
struct verlet {
  template <class S>
  using stepper = Verlet<S>;
  static constexpr IntegratorInfo info{
      "verlet", IntegratorKind::symplectic_splitting, 2, true, false, true, true,
      "Stormer-Verlet (kick-drift-kick), order 2, separable kernels"};
};
struct yoshida6 {
  template <class S>
  using stepper = Yoshida6<S>;
  static constexpr IntegratorInfo info{
      "yoshida6", IntegratorKind::symplectic_splitting, 6, true, false, true, true,
      "Yoshida's 7-stage composition of Verlet, order 6, separable kernels (Yoshida 1990)"};
};
struct kahanli8 {
  template <class S>
  using stepper = KahanLi8<S>;
  static constexpr IntegratorInfo info{
      "kahanli8", IntegratorKind::symplectic_splitting, 8, true, false, true, true,
      "Kahan-Li 15-stage composition of Verlet, order 8, separable kernels (Kahan & Li 1997)"};
};

}  // namespace integrators

// What visit_integrator hands its callable: the stepper type and the descriptor, both usable in
// constant expressions (if constexpr (decltype(tag)::info.needs_separable) ...).
template <class Entry, class S>
struct IntegratorTag {
  using type = typename Entry::template stepper<S>;
  static constexpr const IntegratorInfo& info = Entry::info;
};

template <class... Entries>
struct IntegratorList {
  static constexpr std::size_t size = sizeof...(Entries);
  static constexpr std::array<IntegratorInfo, size> infos{Entries::info...};
  static constexpr std::array<std::string_view, size> names{Entries::info.name...};
};

// The catalogue, in the order listings show it.
using Integrators = IntegratorList<integrators::rk4, integrators::dopri5, integrators::dop853, integrators::radau5,
                                   integrators::gl4,
                                   integrators::gl6, integrators::gl8, integrators::verlet, integrators::yoshida6,
                                   integrators::kahanli8>;

inline constexpr const auto& integrator_infos = Integrators::infos;
inline constexpr const auto& integrator_names = Integrators::names;

// The descriptor of `name`, or nullptr.
constexpr const IntegratorInfo* find_integrator(std::string_view name) {
  for (const IntegratorInfo& info : integrator_infos)
    if (info.name == name) return &info;
  return nullptr;
}

constexpr bool is_integrator(std::string_view name) { return find_integrator(name) != nullptr; }

// The names of the entries `keep` accepts, joined by `separator` ("rk4, dopri5, ..."), for
// messages and --help.
template <std::predicate<const IntegratorInfo&> Keep>
std::string integrator_list(Keep keep, std::string_view separator = ", ") {
  std::string out;
  for (const IntegratorInfo& info : integrator_infos)
    if (keep(info)) {
      if (!out.empty()) out += separator;
      out += info.name;
    }
  return out;
}

// Every name, joined by `separator`.
inline std::string integrator_list(std::string_view separator = ", ") {
  return integrator_list([](const IntegratorInfo&) { return true; }, separator);
}

namespace detail {

template <class S, class F, class Entry, class... Rest>
decltype(auto) visit_integrator_from(std::string_view name, F& f) {
  if (name == Entry::info.name) return f(IntegratorTag<Entry, S>{});
  if constexpr (sizeof...(Rest) == 0) {
    throw std::invalid_argument("unknown integrator '" + std::string(name) + "' (known: " + integrator_list() + ")");
  } else {
    return visit_integrator_from<S, F, Rest...>(name, f);
  }
}

template <class S, class F, class... Entries>
decltype(auto) visit_integrator_in(std::string_view name, F& f, IntegratorList<Entries...>) {
  return visit_integrator_from<S, F, Entries...>(name, f);
}

}  // namespace detail

// Calls f(IntegratorTag<entry, S>{}) for the entry named `name` and returns what f returns (the
// same type for every entry); throws std::invalid_argument for an unknown name.
template <class S, class F>
decltype(auto) visit_integrator(std::string_view name, F&& f) {
  return detail::visit_integrator_in<S>(name, f, Integrators{});
}

}  // namespace eomc::runtime
