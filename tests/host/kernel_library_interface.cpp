// KernelLibrary's public interface, member by member: host/simulate/, the ensembles and the
// tests are written against it, and most of it is made from runtime/kernel/blocks.def, so a row
// renamed or a shape changed there must fail here, at compile time, and not in a caller.
#define BOOST_TEST_MODULE kernel_library_interface
#include <boost/test/unit_test.hpp>

#include <array>
#include <string>
#include <type_traits>
#include <vector>

#include "host/kernel_loader.hpp"

namespace {

using Library = eomc::host::KernelLibrary;
using Parameters = Library::Parameters;
template <class T>
using Getter = const T& (Library::*)() const;
using Names = Getter<std::vector<std::string>>;
template <class T>
using Value = T (Library::*)() const;
using Rates = void (Library::*)(double, const double*, double*, const Parameters&) const;

static_assert(std::is_same_v<decltype(&Library::load),
                             Library (*)(const std::string&, const std::string&, const std::string&, bool)>);
static_assert(std::is_nothrow_move_constructible_v<Library> && std::is_nothrow_move_assignable_v<Library>);
static_assert(!std::is_copy_constructible_v<Library> && !std::is_copy_assignable_v<Library>);
static_assert(std::is_same_v<Parameters, std::unique_ptr<void, Library::ParameterDeleter>>);

// Every kernel's part.
static_assert(std::is_same_v<decltype(&Library::scene_name), Getter<std::string>>);
static_assert(std::is_same_v<decltype(&Library::state_names), Names>);
static_assert(std::is_same_v<decltype(&Library::parameter_names), Names>);
static_assert(std::is_same_v<decltype(&Library::invariant_names), Names>);
static_assert(std::is_same_v<decltype(&Library::output_names), Names>);
static_assert(std::is_same_v<decltype(&Library::initial_state), Getter<std::vector<double>>>);
static_assert(std::is_same_v<decltype(&Library::parameter_defaults), Getter<std::vector<double>>>);
static_assert(std::is_same_v<decltype(&Library::make_parameters),
                             Parameters (Library::*)(const std::vector<double>&) const>);
static_assert(std::is_same_v<decltype(&Library::rhs), Rates>);
static_assert(std::is_same_v<decltype(&Library::invariants), Rates>);
static_assert(std::is_same_v<decltype(&Library::outputs), Rates>);
static_assert(std::is_same_v<decltype(&Library::n_coordinates), Value<int>>);
static_assert(std::is_same_v<decltype(&Library::velocity_offset), Value<int>>);
static_assert(std::is_same_v<decltype(&Library::n_velocities), Value<int>>);
static_assert(std::is_same_v<decltype(&Library::mass_matrix), Rates>);
static_assert(std::is_same_v<decltype(&Library::forcing), Rates>);

// The optional blocks.
static_assert(std::is_same_v<decltype(&Library::variational), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::variational_rhs), Rates>);
static_assert(std::is_same_v<decltype(&Library::has_jacobian), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::jacobian), Rates>);
static_assert(std::is_same_v<decltype(&Library::projects), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::project), void (Library::*)(double, double*, const Parameters&) const>);
static_assert(std::is_same_v<decltype(&Library::separable), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::acceleration), Rates>);
static_assert(std::is_same_v<decltype(&Library::event_names), Names>);
static_assert(std::is_same_v<decltype(&Library::event_directions), Getter<std::vector<int>>>);
static_assert(std::is_same_v<decltype(&Library::event_terminal), Getter<std::vector<bool>>>);
static_assert(std::is_same_v<decltype(&Library::events), Rates>);
static_assert(std::is_same_v<decltype(&Library::constraint_names), Names>);
static_assert(std::is_same_v<decltype(&Library::constraint_residuals), Rates>);
static_assert(std::is_same_v<decltype(&Library::constraint_holonomic), Getter<std::vector<bool>>>);
static_assert(std::is_same_v<decltype(&Library::has_constraint_rows), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::constraint_rows),
                             void (Library::*)(double, const double*, double*, double*, double*, double*,
                                               const Parameters&) const>);
static_assert(std::is_same_v<decltype(&Library::program_names), Names>);
static_assert(std::is_same_v<decltype(&Library::program_laws), Getter<std::vector<std::array<double, 4>>>>);
static_assert(std::is_same_v<decltype(&Library::program_residuals), Rates>);
static_assert(std::is_same_v<decltype(&Library::singular_set_names), Names>);
static_assert(std::is_same_v<decltype(&Library::singular_set_orders), Getter<std::vector<int>>>);
static_assert(std::is_same_v<decltype(&Library::singular_sets), Rates>);
static_assert(std::is_same_v<decltype(&Library::contact_names), Names>);
static_assert(std::is_same_v<decltype(&Library::contact_kinematic), Getter<std::vector<bool>>>);
static_assert(std::is_same_v<decltype(&Library::restitutions), void (Library::*)(const Parameters&, double*) const>);
static_assert(std::is_same_v<decltype(&Library::gaps), Rates>);
static_assert(std::is_same_v<decltype(&Library::contact_jacobian), Rates>);
static_assert(std::is_same_v<decltype(&Library::contact_bias), Rates>);
static_assert(std::is_same_v<decltype(&Library::moving_contacts), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::contact_time_rates), Rates>);

// Batches.
static_assert(std::is_same_v<decltype(&Library::batch_width), Value<int>>);
static_assert(std::is_same_v<decltype(&Library::make_batch_parameters),
                             Parameters (Library::*)(const std::vector<double>&) const>);
static_assert(std::is_same_v<decltype(&Library::rhs_batch), Rates>);
static_assert(std::is_same_v<decltype(&Library::invariants_batch), Rates>);

// How the library was obtained.
static_assert(std::is_same_v<decltype(&Library::library_path), Getter<std::string>>);
static_assert(std::is_same_v<decltype(&Library::cache_hit), Value<bool>>);
static_assert(std::is_same_v<decltype(&Library::seconds), Value<double>>);

}  // namespace

// The checks above are the test; a case makes their compilation visible in CTest.
BOOST_AUTO_TEST_CASE(the_public_interface_is_unchanged) { BOOST_TEST(true); }
