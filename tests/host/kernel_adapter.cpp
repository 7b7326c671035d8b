// The adapter (templates/kernel_adapter.cpp) as the suite compiles it (tests/host/CMakeLists.txt),
// loaded, against the kernel it was compiled with: every row of runtime/kernel/blocks.def says
// whether the kernel has its block and how many rows, the functions compute what the kernel does,
// and a kernel without moving gaps gets w = 0.
#define BOOST_TEST_MODULE kernel_adapter
#include <boost/test/unit_test.hpp>

#include <dlfcn.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <eomc/runtime/kernel.hpp>
#include <eomc/runtime/kernel/c_interface.hpp>

#include "attitude_slew.hpp"
#include "ball_vibrating_table.hpp"
#include "knife_edge_sled_wall.hpp"
#include "lagrange_top.hpp"

namespace {

namespace rt = eomc::runtime;
namespace c = eomc::runtime::kernel_c;

const c::VTable& vtable_of(const char* module) {
    void* handle = ::dlopen(module, RTLD_NOW | RTLD_LOCAL);  // kept open: the tables live in it
    BOOST_REQUIRE_MESSAGE(handle, ::dlerror());
    BOOST_TEST(reinterpret_cast<int (*)()>(::dlsym(handle, "eomc_adapter_abi"))() == c::abi);
    const auto vtable = reinterpret_cast<const c::VTable* (*)()>(::dlsym(handle, "eomc_kernel_vtable"));
    BOOST_REQUIRE(vtable);
    BOOST_TEST(std::strcmp(vtable()->blocks, c::block_table) == 0);
    return *vtable();
}

// The adapter compiled with K, loaded, with its blocks checked row by row.
template <class K>
const c::VTable& loaded(const char* module) {
    const c::VTable& vt = vtable_of(module);
    BOOST_TEST(vt.n_state == K::n_state);
    BOOST_TEST(std::string(vt.scene_name) == K::scene_name);
    // Each group of rows: its count, and its names where the kernel has the block.
#define EOMC_KERNEL_ROWS(concept, count, names)                                     \
    if constexpr (rt::concept<K>) {                                                 \
        BOOST_TEST(vt.count == K::count, #count);                                   \
        for (int i = 0; i < vt.count; ++i) BOOST_TEST(std::string(vt.names[i]) == K::names[i]); \
    } else {                                                                        \
        BOOST_TEST(vt.count == 0, #count);                                          \
        BOOST_TEST(!vt.names, #names);                                              \
    }
#define EOMC_KERNEL_FUNCTION(concept, name, shape) BOOST_TEST(vt.has_##name == rt::concept<K>, #name);
#include <eomc/runtime/kernel/blocks.def>
    return vt;
}

// rhs and a block's function through the vtable, against the kernel's own at its initial state.
template <class K>
void check_rates(const c::VTable& vt, void (*through_vtable)(double, const double*, double*, const void*),
                 void (*kernel)(double, const double*, double*, const typename K::Parameters&), int n) {
    const typename K::Parameters p{};
    std::vector<double> expected(std::size_t(n), 0.0), got(std::size_t(n), std::nan(""));
    kernel(0.25, K::initial_state.data(), expected.data(), p);
    void* parameters = vt.create_parameters(vt.parameter_defaults);
    through_vtable(0.25, K::initial_state.data(), got.data(), parameters);
    vt.destroy_parameters(parameters);
    BOOST_TEST(got == expected, boost::test_tools::per_element());
}

}  // namespace

BOOST_AUTO_TEST_CASE(events_jacobian_projection_and_the_batch) {
    using K = eomc::models::LagrangeTop;
    const c::VTable& vt = loaded<K>(ADAPTER_LAGRANGE_TOP);
    BOOST_TEST(vt.batch_width == 4);
    check_rates<K>(vt, vt.rhs, K::rhs<double>, K::n_state);
    check_rates<K>(vt, vt.jacobian, K::jacobian<double>, K::n_state * K::n_state);
    check_rates<K>(vt, vt.events, K::events<double>, K::n_events);
}

BOOST_AUTO_TEST_CASE(constraint_rows_beside_fixed_contacts) {
    using K = eomc::models::KnifeEdgeSledWall;
    const c::VTable& vt = loaded<K>(ADAPTER_KNIFE_EDGE_SLED_WALL);
    BOOST_TEST(vt.batch_width == 0);
    check_rates<K>(vt, vt.gaps, K::gaps<double>, K::n_contacts);
    check_rates<K>(vt, vt.constraint_residuals, K::constraint_residuals<double>, K::n_constraints);
    // Fixed walls: w = 0, one per contact row.
    check_rates<K>(vt, vt.contact_time_rates, [](double, const double*, double* out, const K::Parameters&) {
        for (int i = 0; i < K::n_contacts; ++i) out[i] = 0.0;
    }, K::n_contacts);
}

BOOST_AUTO_TEST_CASE(moving_contacts) {
    using K = eomc::models::BallVibratingTable;
    const c::VTable& vt = loaded<K>(ADAPTER_BALL_VIBRATING_TABLE);
    check_rates<K>(vt, vt.contact_time_rates, K::contact_time_rates<double>, K::n_contacts);
}

BOOST_AUTO_TEST_CASE(programs_and_singular_sets) {
    using K = eomc::models::AttitudeSlew;
    const c::VTable& vt = loaded<K>(ADAPTER_ATTITUDE_SLEW);
    for (int i = 0; i < 4 * K::n_programs; ++i) BOOST_TEST(vt.program_laws[i] == K::program_laws[std::size_t(i)]);
    check_rates<K>(vt, vt.program_residuals, K::program_residuals<double>, 2 * K::n_programs);
    check_rates<K>(vt, vt.singular_sets, K::singular_sets<double>, K::n_singular_sets);
}
