#pragma once

// The integrators' stepper types, paired with their descriptors in the catalogue
// (registry_info.hpp, which says each method's name, kind, order and traits), and the dispatch from
// a name to its stepper. Code that only lists, validates or judges methods includes
// registry_info.hpp alone; code that runs them includes this.
//
// Adding an integrator: its stepper header under stepper/, its descriptor in registry_info.hpp, one
// entry below and its name in IntegratorList; tests/runtime/registry.cpp then checks that it
// dispatches and that the declared order and traits are the stepper's.

#include <array>
#include <concepts>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

#include "eomc/runtime/registry_info.hpp"
#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "eomc/runtime/stepper/gauss_legendre.hpp"
#include "eomc/runtime/stepper/radau5.hpp"
#include "eomc/runtime/stepper/rk4.hpp"
#include "eomc/runtime/stepper/splitting.hpp"

namespace eomc::runtime {

namespace integrators {

// One struct per method: `stepper<S>` is its runtime type, `info` its descriptor in the catalogue.
#define EOMC_INTEGRATOR_ENTRY(entry, Stepper)                                                 \
  struct entry {                                                                              \
    template <class S>                                                                        \
    using stepper = Stepper<S>;                                                               \
    static constexpr const IntegratorInfo& info = integrator_infos[integrator_index(#entry)]; \
  };
EOMC_INTEGRATOR_ENTRY(rk4, Rk4)
EOMC_INTEGRATOR_ENTRY(dopri5, Dopri5)
EOMC_INTEGRATOR_ENTRY(dop853, Dop853)
EOMC_INTEGRATOR_ENTRY(radau5, Radau5)
EOMC_INTEGRATOR_ENTRY(gl4, Gl4)
EOMC_INTEGRATOR_ENTRY(gl6, Gl6)
EOMC_INTEGRATOR_ENTRY(gl8, Gl8)
EOMC_INTEGRATOR_ENTRY(verlet, Verlet)
EOMC_INTEGRATOR_ENTRY(yoshida6, Yoshida6)
EOMC_INTEGRATOR_ENTRY(kahanli8, KahanLi8)
#undef EOMC_INTEGRATOR_ENTRY

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
};

// The catalogue, in the order listings show it.
using Integrators = IntegratorList<integrators::rk4, integrators::dopri5, integrators::dop853, integrators::radau5,
                                   integrators::gl4,
                                   integrators::gl6, integrators::gl8, integrators::verlet, integrators::yoshida6,
                                   integrators::kahanli8>;

// Every descriptor has its stepper, in the catalogue's order.
template <class... Entries>
constexpr bool lists_the_catalogue(IntegratorList<Entries...>) {
  std::size_t i = 0;
  return sizeof...(Entries) == integrator_infos.size() && ((Entries::info.name == integrator_infos[i++].name) && ...);
}
static_assert(lists_the_catalogue(Integrators{}), "registry.hpp and registry_info.hpp list different integrators");

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
