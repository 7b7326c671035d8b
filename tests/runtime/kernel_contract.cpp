// runtime/kernel.hpp: the concepts accept a kernel of the documented shape and reject one that
// lacks a part or has it in another shape; PositionalParameters is what lets a host fill a
// kernel's Parameters by position, as the loader's C adapter does.
#define BOOST_TEST_MODULE runtime_kernel_contract
#include <boost/test/unit_test.hpp>

#include <array>
#include <bit>
#include <cstddef>
#include <type_traits>

#include "eomc/runtime/float128.hpp"
#include "eomc/runtime/kernel.hpp"

namespace {

namespace rt = eomc::runtime;

// The base, in the shape of the hand-written kernel tests/bench/driver compiles the bench with.
struct Base {
  static constexpr int n_coordinates = 1;
  static constexpr int n_state = 2;
  static constexpr int n_parameters = 2;
  static constexpr int n_invariants = 1;
  static constexpr const char* scene_name = "base";
  static constexpr std::array<const char*, n_state> state_names{"x", "x_dot"};
  static constexpr std::array<const char*, n_parameters> parameter_names{"k", "m"};
  static constexpr std::array<const char*, n_invariants> invariant_names{"energy"};
  static constexpr std::array<double, n_state> initial_state{1, 0};
  struct Parameters {
    double k = 2;
    double m = 3;
  };
  template <class S>
  static void rhs(S, const S* x, S* dxdt, const Parameters& p) {
    dxdt[0] = x[1];
    dxdt[1] = -S(p.k) / S(p.m) * x[0];
  }
  template <class S>
  static void invariants(S, const S* x, S* out, const Parameters& p) {
    out[0] = (S(p.m) * x[1] * x[1] + S(p.k) * x[0] * x[0]) / S(2);
  }
};

// What templates/kernel.hpp.in prints for a kernel generated without jacobian().
struct WithoutJacobian : Base {
  static constexpr int velocity_offset = 1;
  static constexpr int n_velocities = 1;
  static constexpr int n_outputs = 1;
  static constexpr bool separable = true;
  static constexpr bool has_jacobian = false;
  static constexpr std::array<const char*, n_outputs> output_names{"force"};
  template <class S>
  static void mass_matrix(S, const S*, S* out, const Parameters& p) { out[0] = S(p.m); }
  template <class S>
  static void forcing(S, const S* x, S* out, const Parameters& p) { out[0] = -S(p.k) * x[0]; }
  template <class S>
  static void outputs(S, const S* x, S* out, const Parameters& p) { out[0] = -S(p.k) * x[0]; }
};

// Everything templates/kernel.hpp.in prints (jacobian() included), plus events and a projection.
struct Full : WithoutJacobian {
  static constexpr bool has_jacobian = true;
  template <class S>
  static void jacobian(S, const S*, S* out, const Parameters& p) {
    out[0] = S(0), out[1] = S(1), out[2] = -S(p.k) / S(p.m), out[3] = S(0);
  }
  template <class S>
  static void acceleration(S, const S* q, S* a, const Parameters& p) { a[0] = -S(p.k) / S(p.m) * q[0]; }
  template <class S>
  static void project(S, S*, const Parameters&) {}
  static constexpr int n_events = 1;
  static constexpr std::array<const char*, n_events> event_names{"crossing"};
  static constexpr std::array<int, n_events> event_directions{1};
  static constexpr std::array<bool, n_events> event_terminal{false};
  template <class S>
  static void events(S, const S* x, S* out, const Parameters&) { out[0] = x[0]; }
};

// One part missing or misshapen each.
struct ClaimsJacobian : WithoutJacobian {
  static constexpr bool has_jacobian = true;
};
struct HidesJacobian : Full {
  static constexpr bool has_jacobian = false;
};
struct NoRhs {
  static constexpr int n_coordinates = 1, n_state = 1, n_parameters = 0, n_invariants = 0;
  static constexpr const char* scene_name = "no_rhs";
  static constexpr std::array<const char*, 1> state_names{"x"};
  static constexpr std::array<const char*, 0> parameter_names{};
  static constexpr std::array<const char*, 0> invariant_names{};
  static constexpr std::array<double, 1> initial_state{0};
  struct Parameters {};
  template <class S>
  static void invariants(S, const S*, S*, const Parameters&) {}
};
struct ShortNames : Base {
  static constexpr std::array<const char*, 1> state_names{"x"};  // n_state is 2
};
struct EventsWithoutDirections : Base {
  static constexpr int n_events = 1;
  static constexpr std::array<const char*, n_events> event_names{"crossing"};
  static constexpr std::array<bool, n_events> event_terminal{false};
  template <class S>
  static void events(S, const S* x, S* out, const Parameters&) { out[0] = x[0]; }
};
struct RhsForDoubleOnly : Base {  // every function must be a template over the scalar
  static void rhs(double, const double*, double*, const Parameters&) {}
};
struct RhsForFloatingPointOnly : Base {  // rhs for the built-in types, not float128
  template <class S>
    requires std::is_floating_point_v<S>
  static void rhs(S, const S*, S*, const Parameters&) {}
};
struct ParametersWithAnInt : Base {
  struct Parameters {
    double k = 2;
    int m = 3;
  };
  template <class S>
  static void rhs(S, const S*, S*, const Parameters&) {}
  template <class S>
  static void invariants(S, const S*, S*, const Parameters&) {}
};

static_assert(rt::Kernel<Base> && rt::Kernel<Base, long double> && rt::Kernel<Base, rt::float128>);
static_assert(!rt::GeneratedKernel<Base> && !rt::SeparableKernel<Base> && !rt::EventKernel<Base> &&
              !rt::ProjectingKernel<Base> && !rt::KernelWithOutputs<Base>);
static_assert(rt::GeneratedKernel<Full> && rt::SeparableKernel<Full> && rt::EventKernel<Full> &&
              rt::ProjectingKernel<Full>);
static_assert(!rt::VariationalKernel<Full> && !rt::SantilliKernel<Full>);
// jacobian() is optional, and has_jacobian must say whether it is there.
static_assert(rt::GeneratedKernel<WithoutJacobian> && !rt::KernelWithJacobian<WithoutJacobian> &&
              rt::KernelWithJacobian<Full>);
static_assert(!rt::GeneratedKernel<ClaimsJacobian> && !rt::GeneratedKernel<HidesJacobian>);
static_assert(!rt::Kernel<NoRhs>);
static_assert(!rt::Kernel<ShortNames>);
static_assert(rt::Kernel<EventsWithoutDirections> && !rt::EventKernel<EventsWithoutDirections>);
static_assert(!rt::Kernel<RhsForDoubleOnly>);
static_assert(rt::Kernel<RhsForFloatingPointOnly, long double> && !rt::Kernel<RhsForFloatingPointOnly, rt::float128>);
static_assert(rt::PositionalParameters<Base> && !rt::PositionalParameters<ParametersWithAnInt>);

}  // namespace

// What the adapter relies on: aggregate initialisation fills the parameters in parameter_names
// order, and the defaults read back as an array of doubles in that order.
BOOST_AUTO_TEST_CASE(positional_parameters_round_trip) {
  const auto defaults = std::bit_cast<std::array<double, Base::n_parameters>>(Base::Parameters{});
  BOOST_TEST(defaults[0] == 2.0);
  BOOST_TEST(defaults[1] == 3.0);
}
