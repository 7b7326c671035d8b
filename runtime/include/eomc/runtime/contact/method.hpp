#pragma once

// The contact drivers and impact laws by name, and the rules their settings obey: one table each,
// read by the scene's [contact] reader, the command line's --contact-method and --impact-law, and
// the run's request, so that a name or a range is spelled and checked in one place. No Eigen here:
// readers of scenes and flags include it without the drivers.

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eomc::runtime::contact {

// How a run integrates through unilateral rows: the event-driven hybrid driver (event_driven.hpp:
// free flight, impacts located as events, contact phases, Zeno points) or Moreau–Jean's time
// stepping (moreau_jean.hpp; V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical
// Systems, Springer 2008).
enum class ContactMethod { event_driven, moreau_jean };

// How the event-driven driver resolves an impact on several closed contacts: Moreau's LCP over all
// of them at once, or one two-body impact after another (impact.hpp). Moreau–Jean's step LCP is
// the simultaneous law by construction.
enum class ImpactLaw { simultaneous, sequential };

template <class Enum>
struct NamedChoice {
  std::string_view name;
  Enum value;
};

inline constexpr std::array<NamedChoice<ContactMethod>, 2> contact_methods{
    {{"event_driven", ContactMethod::event_driven}, {"moreau_jean", ContactMethod::moreau_jean}}};
inline constexpr std::array<NamedChoice<ImpactLaw>, 2> impact_laws{
    {{"simultaneous", ImpactLaw::simultaneous}, {"sequential", ImpactLaw::sequential}}};

namespace detail {
template <class Enum, std::size_t n>
constexpr std::optional<Enum> find(const std::array<NamedChoice<Enum>, n>& table, std::string_view name) {
  for (const auto& entry : table)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}
template <class Enum, std::size_t n>
constexpr std::string_view name_in(const std::array<NamedChoice<Enum>, n>& table, Enum value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}
template <class Enum, std::size_t n>
std::vector<std::string> names_in(const std::array<NamedChoice<Enum>, n>& table) {
  std::vector<std::string> out;
  for (const auto& entry : table) out.emplace_back(entry.name);
  return out;
}
}  // namespace detail

constexpr std::optional<ContactMethod> find_contact_method(std::string_view name) {
  return detail::find(contact_methods, name);
}
constexpr std::optional<ImpactLaw> find_impact_law(std::string_view name) { return detail::find(impact_laws, name); }
constexpr std::string_view name(ContactMethod method) { return detail::name_in(contact_methods, method); }
constexpr std::string_view name(ImpactLaw law) { return detail::name_in(impact_laws, law); }
inline std::vector<std::string> contact_method_names() { return detail::names_in(contact_methods); }
inline std::vector<std::string> impact_law_names() { return detail::names_in(impact_laws); }

// Newton's coefficient of restitution: e in [0, 1] (0 plastic, 1 elastic; Mei ch. 6).
constexpr bool valid_restitution(double e) { return e >= 0.0 && e <= 1.0; }

// Moreau–Jean's θ in [1/2, 1]: the θ-method is unconditionally stable there (1/2 exact on
// constant forces, 1 backward Euler); below 1/2 it amplifies oscillations (Acary & Brogliato 2008).
constexpr bool valid_theta(double theta) { return theta >= 0.5 && theta <= 1.0; }

}  // namespace eomc::runtime::contact
