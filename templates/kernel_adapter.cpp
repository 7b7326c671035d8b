// eomc simulate: the C interface (eomc/runtime/kernel/c_interface.hpp) over one generated kernel.
// The loader (generator/host/kernel_loader.cpp) compiles this file, embedded in the generator,
// into a shared object with the kernel's header beside it and loads it with dlopen; the tests
// compile it against bundled kernels (tests/host/CMakeLists.txt). It is told which kernel by
//   -DEOMC_KERNEL_HEADER="kernel.hpp"                        the generated header
//   -DEOMC_KERNEL_STRUCT=Name                                its kernel, eomc::models::Name
//   -DEOMC_KERNEL_IDENTITY="Name <SHA-256 of the header>"    checked by the loader once loaded
// and, for an ensemble run with --batch only,
//   -DEOMC_KERNEL_BATCH                                      the batched rhs and invariants
// whose <experimental/simd> costs four times the rest of the compile (a separate cache entry).
#if !defined(EOMC_KERNEL_HEADER) || !defined(EOMC_KERNEL_STRUCT) || !defined(EOMC_KERNEL_IDENTITY)
#error "kernel_adapter.cpp: define EOMC_KERNEL_HEADER, EOMC_KERNEL_STRUCT and EOMC_KERNEL_IDENTITY"
#endif
#include EOMC_KERNEL_HEADER

#include <array>
#include <bit>
#include <cstddef>
#include <utility>

#include <eomc/runtime/kernel.hpp>
#include <eomc/runtime/kernel/c_interface.hpp>
#ifdef EOMC_KERNEL_BATCH
#include <experimental/simd>
#endif

// The kernel's template over its parameters' scalar, Basic<Name>.
#define EOMC_PASTE(a, b) a##b
#define EOMC_BASIC_KERNEL(name) EOMC_PASTE(Basic, name)

namespace {
namespace rt = eomc::runtime;
namespace c = eomc::runtime::kernel_c;
using K = eomc::models::EOMC_KERNEL_STRUCT;
using P = K::Parameters;
constexpr std::size_t n_par = K::n_parameters;

static_assert(rt::GeneratedKernel<K>, "eomc simulate: the header does not define a kernel of eomc's shape");
// Aggregate initialisation then fills the parameters by position, and their bytes are an array of doubles.
static_assert(rt::PositionalParameters<K>,
              "eomc simulate: Parameters must be a plain aggregate of exactly n_parameters doubles");

template <class M>
const typename M::Parameters& parameters_of(const void* p) {
    return *static_cast<const typename M::Parameters*>(p);
}
template <class... Arguments>
void unused(const Arguments&...) {}

// --- every kernel's part ----------------------------------------------------------------------

template <std::size_t... I>
void* create(const double* v, std::index_sequence<I...>) {
    (void)v;
    return new P{v[I]...};
}
void* create_parameters(const double* values) { return create(values, std::make_index_sequence<n_par>{}); }
void destroy_parameters(void* p) { delete static_cast<P*>(p); }

// The scene's values: the bytes of a default Parameters.
std::array<double, n_par> default_parameters() {
    if constexpr (n_par > 0) return std::bit_cast<std::array<double, n_par>>(P{});
    else return {};
}
const std::array<double, n_par> parameter_defaults = default_parameters();

void rhs(EOMC_KERNEL_SHAPE_rates(const void*)) { K::rhs<double>(t, x, out, parameters_of<K>(p)); }
void invariants(EOMC_KERNEL_SHAPE_rates(const void*)) { K::invariants<double>(t, x, out, parameters_of<K>(p)); }
void outputs(EOMC_KERNEL_SHAPE_rates(const void*)) { K::outputs<double>(t, x, out, parameters_of<K>(p)); }
void mass_matrix(EOMC_KERNEL_SHAPE_rates(const void*)) { K::mass_matrix<double>(t, x, out, parameters_of<K>(p)); }
void forcing(EOMC_KERNEL_SHAPE_rates(const void*)) { K::forcing<double>(t, x, out, parameters_of<K>(p)); }

// --- batches (EOMC_KERNEL_BATCH) -----------------------------------------------------------------
#ifdef EOMC_KERNEL_BATCH

// A batchable kernel's rhs and invariants over batch_width members per call: S and the parameters'
// scalar a SIMD batch, one member per lane; the arrays lane-minor (a[i * batch_width + lane]).
// Templates on M = Basic<Name><Lanes>, so that nothing is instantiated for a kernel that is not
// K::batchable (its code solves or branches). Not a row of blocks.def: the batch is the kernel's
// other instantiation, not a block of its own.
constexpr std::size_t batch_width = 4;  // two SSE2 registers of doubles
using Lanes = std::experimental::fixed_size_simd<double, batch_width>;
using BatchKernel = eomc::models::EOMC_BASIC_KERNEL(EOMC_KERNEL_STRUCT)<Lanes>;
constexpr auto lane_minor = std::experimental::element_aligned;

template <class M, std::size_t... I>
void* create_batch(const double* v, std::index_sequence<I...>) {
    (void)v;
    if constexpr (K::batchable) return new typename M::Parameters{Lanes(v + I * batch_width, lane_minor)...};
    else return nullptr;
}
template <class M>
void destroy_batch(void* p) {
    if constexpr (K::batchable) delete static_cast<typename M::Parameters*>(p);
    else (void)p;
}
template <class M>
void rhs_batch(EOMC_KERNEL_SHAPE_rates(const void*)) {
    if constexpr (K::batchable) {
        std::array<Lanes, K::n_state> xs, rates;
        for (std::size_t i = 0; i < xs.size(); ++i) xs[i].copy_from(x + i * batch_width, lane_minor);
        M::rhs(Lanes(t), xs.data(), rates.data(), parameters_of<M>(p));
        for (std::size_t i = 0; i < xs.size(); ++i) rates[i].copy_to(out + i * batch_width, lane_minor);
    } else {
        unused(t, x, out, p);
    }
}
template <class M>
void invariants_batch(EOMC_KERNEL_SHAPE_rates(const void*)) {
    if constexpr (K::batchable) {
        std::array<Lanes, K::n_state> xs;
        std::array<Lanes, K::n_invariants> values;
        for (std::size_t i = 0; i < xs.size(); ++i) xs[i].copy_from(x + i * batch_width, lane_minor);
        M::invariants(Lanes(t), xs.data(), values.data(), parameters_of<M>(p));
        for (std::size_t i = 0; i < values.size(); ++i) values[i].copy_to(out + i * batch_width, lane_minor);
    } else {
        unused(t, x, out, p);
    }
}
void* create_batch_parameters(const double* values) {
    return create_batch<BatchKernel>(values, std::make_index_sequence<n_par>{});
}
#else
constexpr std::size_t batch_width = 0;  // not compiled: the loader asks for it with --batch only
#endif

// --- the optional blocks, one template per row of blocks.def -------------------------------------

// Templates on M = K, so that the branch for a kernel without the block is discarded.
namespace blocks {
#define EOMC_KERNEL_ROWS(concept, count, names)                   \
    template <class M>                                            \
    constexpr int count() {                                       \
        if constexpr (rt::concept<M>) return int(M::count);       \
        else return 0;                                            \
    }                                                             \
    template <class M>                                            \
    constexpr const char* const* names() {                        \
        if constexpr (rt::concept<M>) return M::names.data();     \
        else return nullptr;                                      \
    }
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width)                             \
    template <class M>                                                                      \
    constexpr const type* column() {                                                        \
        if constexpr (rt::concept<M>) {                                                     \
            static_assert(M::column.size() == std::size_t(width) * std::size_t(M::count),   \
                          #column " must hold " #width " values per row");                   \
            return M::column.data();                                                        \
        } else {                                                                            \
            return nullptr;                                                                 \
        }                                                                                   \
    }
#define EOMC_KERNEL_FUNCTION_OR_ZEROS(concept, name, shape, count)                                  \
    template <class M>                                                                              \
    void name(EOMC_KERNEL_SHAPE_##shape(const void*)) {                                             \
        if constexpr (rt::concept<M>) {                                                             \
            M::template name<double>(EOMC_KERNEL_CALL_##shape(parameters_of<M>(p)));                \
        } else {                                                                                    \
            unused(EOMC_KERNEL_CALL_##shape(p));                                                    \
            for (int i = 0; i < count<M>(); ++i) out[i] = 0.0;                                      \
        }                                                                                           \
    }
#define EOMC_KERNEL_FUNCTION(concept, name, shape)                                                  \
    template <class M>                                                                              \
    void name(EOMC_KERNEL_SHAPE_##shape(const void*)) {                                             \
        if constexpr (rt::concept<M>) M::template name<double>(EOMC_KERNEL_CALL_##shape(parameters_of<M>(p))); \
        else unused(EOMC_KERNEL_CALL_##shape(p));                                                   \
    }
#include <eomc/runtime/kernel/blocks.def>
}  // namespace blocks

const c::VTable vtable{
    .blocks = c::block_table,
    .scene_name = K::scene_name,
    .n_state = K::n_state,
    .n_parameters = K::n_parameters,
    .n_invariants = K::n_invariants,
    .n_outputs = K::n_outputs,
    .state_names = K::state_names.data(),
    .parameter_names = K::parameter_names.data(),
    .invariant_names = K::invariant_names.data(),
    .output_names = K::output_names.data(),
    .initial_state = K::initial_state.data(),
    .parameter_defaults = parameter_defaults.data(),
    .create_parameters = create_parameters,
    .destroy_parameters = destroy_parameters,
    .rhs = rhs,
    .invariants = invariants,
    .outputs = outputs,
    .n_coordinates = K::n_coordinates,
    .velocity_offset = K::velocity_offset,
    .n_velocities = K::n_velocities,
    .mass_matrix = mass_matrix,
    .forcing = forcing,
    .batch_width = K::batchable ? int(batch_width) : 0,
#ifdef EOMC_KERNEL_BATCH
    .create_batch_parameters = create_batch_parameters,
    .destroy_batch_parameters = destroy_batch<BatchKernel>,
    .rhs_batch = rhs_batch<BatchKernel>,
    .invariants_batch = invariants_batch<BatchKernel>,
#else
    .create_batch_parameters = nullptr,
    .destroy_batch_parameters = nullptr,
    .rhs_batch = nullptr,
    .invariants_batch = nullptr,
#endif
#define EOMC_KERNEL_ROWS(concept, count, names) .count = blocks::count<K>(), .names = blocks::names<K>(),
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width) .column = blocks::column<K>(),
#define EOMC_KERNEL_FUNCTION(concept, name, shape) .has_##name = rt::concept<K>, .name = blocks::name<K>,
#include <eomc/runtime/kernel/blocks.def>
};
}  // namespace

#define EOMC_EXPORT extern "C" __attribute__((visibility("default")))

EOMC_EXPORT int eomc_adapter_abi() { return c::abi; }
// Which kernel this is: the struct and the SHA-256 of the header it was compiled from.
EOMC_EXPORT const char* eomc_kernel_identity() { return EOMC_KERNEL_IDENTITY; }
EOMC_EXPORT const c::VTable* eomc_kernel_vtable() { return &vtable; }
