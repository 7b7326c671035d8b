#pragma once

// The one exception type the integrators throw when they cannot make progress.

#include <charconv>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace eomc::runtime {

class IntegrationError : public std::runtime_error {
 public:
  enum class Kind { step_underflow, step_budget, non_finite, singular_set, event_loop, contact };
  static constexpr std::size_t no_component = static_cast<std::size_t>(-1);

  IntegrationError(Kind kind, double t, const std::string& message, std::size_t component = no_component)
      : std::runtime_error(message), kind_(kind), t_(t), component_(component) {}

  // The factories format times in the integration's own scalar, so a long double run reports
  // t = 0.49999999999999999995 rather than its double rounding 0.5; t() is always a double.

  // "step size collapsed to 3.1e-17 at t = 1.2345 (step underflow)"
  template <class S>
  static IntegrationError step_underflow(S t, S h) {
    return {Kind::step_underflow, static_cast<double>(t),
            "step size collapsed to " + format(h) + " at t = " + format(t) + " (step underflow)"};
  }
  // "step budget of 100 steps exhausted at t = 0.25"
  template <class S>
  static IntegrationError step_budget(S t, std::size_t max_steps) {
    return {Kind::step_budget, static_cast<double>(t),
            "step budget of " + std::to_string(max_steps) + " steps exhausted at t = " + format(t)};
  }
  // "event 0 fired again at t = 0.64 right after its edit there: ..."; events count from 0.
  template <class S>
  static IntegrationError event_loop(S t, std::size_t event) {
    return {Kind::event_loop, static_cast<double>(t),
            "event " + std::to_string(event) + " fired again at t = " + format(t) +
                " right after its edit there: the edited state lies where the event crosses at once, so the "
                "edits would repeat without advancing t (give the event a cooldown, or edit the state off "
                "its surface)"};
  }
  // "non-finite state at t = 0.5 (component 3)"; what is "state" or "derivative"; components count from 0.
  template <class S>
  static IntegrationError non_finite(S t, const std::string& what, std::size_t component) {
    return {Kind::non_finite, static_cast<double>(t),
            "non-finite " + what + " at t = " + format(t) + " (component " + std::to_string(component) + ")",
            component};
  }

  // "contact 1 at t = 0.45: ..." (the contact drivers; contacts count from 0 and the index is kept
  // in component(), which a caller maps to the contact's name).
  template <class S>
  static IntegrationError contact(S t, std::size_t index, const std::string& what) {
    return {Kind::contact, static_cast<double>(t), "contact " + std::to_string(index) + " at t = " + format(t) + ": " + what,
            index};
  }

  Kind kind() const noexcept { return kind_; }
  // The time reached when the integration stopped (the last accepted time).
  double t() const noexcept { return t_; }
  // The offending component for Kind::non_finite, the contact for Kind::contact, no_component
  // otherwise.
  std::size_t component() const noexcept { return component_; }

  // Shortest decimal text that reads back to the same value (scalars that are not built-in
  // floating-point types are shown through double).
  template <class S>
  static std::string format(S v) {
    char buf[64];
    std::to_chars_result res;
    if constexpr (std::is_floating_point_v<S>)
      res = std::to_chars(buf, buf + sizeof buf, v);
    else
      res = std::to_chars(buf, buf + sizeof buf, static_cast<double>(v));
    return std::string(buf, res.ptr);
  }

 private:
  Kind kind_;
  double t_;
  std::size_t component_;
};

}  // namespace eomc::runtime
