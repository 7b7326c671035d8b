// The integrator registry (registry.hpp): unique names, every entry dispatches to its stepper, the
// declared orders and traits are the steppers' own, unknown names are refused.
#define BOOST_TEST_MODULE runtime_registry
#include <boost/test/unit_test.hpp>

#include <set>
#include <stdexcept>
#include <string>
#include <string_view>

#include "eomc/runtime/registry.hpp"

namespace rt = eomc::runtime;

// Checked at compile time too: the lookups are constexpr.
static_assert(rt::is_integrator("dopri5") && !rt::is_integrator("euler"));
static_assert(rt::find_integrator("gl6")->order == 6);

BOOST_AUTO_TEST_CASE(names_are_unique_and_described) {
  std::set<std::string_view> seen;
  for (const rt::IntegratorInfo& info : rt::integrator_infos) {
    BOOST_TEST_CONTEXT(info.name) {
      BOOST_TEST(seen.insert(info.name).second);
      BOOST_TEST(!info.description.empty());
      BOOST_TEST(rt::find_integrator(info.name) == &info);
    }
  }
  BOOST_TEST(seen.size() == rt::Integrators::size);
}

// Every name dispatches to an entry of that name, whose declared order is the stepper's `order`
// and whose traits follow from the stepper's interface: adaptive ones are AdaptiveStepper, dense
// output ones DenseOutputStepper, and only the splitting methods take an acceleration.
BOOST_AUTO_TEST_CASE(every_entry_dispatches_with_the_steppers_order) {
  for (const rt::IntegratorInfo& info : rt::integrator_infos) {
    BOOST_TEST_CONTEXT(info.name) {
      const auto checked = rt::visit_integrator<double>(info.name, [&](auto tag) {
        using Tag = decltype(tag);
        using Stepper = typename Tag::type;
        BOOST_TEST(Tag::info.name == info.name);
        BOOST_TEST(Tag::info.order == Stepper::order);
        BOOST_TEST((Tag::info.kind == rt::IntegratorKind::adaptive) == rt::AdaptiveStepper<Stepper>);
        BOOST_TEST(Tag::info.dense_output == rt::DenseOutputStepper<Stepper>);
        BOOST_TEST(Tag::info.needs_separable == (Tag::info.kind == rt::IntegratorKind::symplectic_splitting));
        BOOST_TEST(Tag::info.fixed_step() == !rt::AdaptiveStepper<Stepper>);
        return std::string(Tag::info.name);
      });
      BOOST_TEST(checked == std::string(info.name));
    }
  }
  // long double dispatches to the same entries.
  BOOST_TEST(rt::visit_integrator<long double>("dop853", [](auto tag) { return decltype(tag)::type::order; }) == 8);
}

BOOST_AUTO_TEST_CASE(unknown_names_are_refused_with_the_list) {
  try {
    rt::visit_integrator<double>("euler", [](auto) { return 0; });
    BOOST_FAIL("no exception for an unknown integrator");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    BOOST_TEST(what.find("euler") != std::string::npos);
    BOOST_TEST(what.find(rt::integrator_list()) != std::string::npos);
  }
  BOOST_TEST(rt::find_integrator("") == nullptr);
}
