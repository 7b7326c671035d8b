#include "host/kernel_loader.hpp"

#include <dlfcn.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "support/identifier.hpp"
#include "support/sha256.hpp"

namespace eomc::host {

namespace fs = std::filesystem;

namespace {

// Bumped whenever the C interface below changes; the loader refuses a library that reports
// another value (a cache written by an older eomc).
constexpr int adapter_abi = 15;  // 3: acceleration and events; 4: project; 5: variational_rhs; 6: project(t, x, p);
                                 // 7: eomc_kernel_identity; 8: constraint rows; 9: singular sets;
                                 // 10: the mechanical form (sizes, M, f) and unilateral rows; 11: programs;
                                 // 12: bilateral rows beside unilateral ones (constraint_rows);
                                 // 13: contact_time_rates (moving gaps; zeros for a kernel without it);
                                 // 14: the batched rhs and invariants (batch_width lanes);
                                 // 15: jacobian (kernels generated with it only)

// The adapter: C functions over double, so that the host needs no knowledge of the kernel's
// C++ types. Parameters travel by position in parameter_names order, never by member name
// (a parameter named like a C++ keyword becomes a member with a trailing underscore).
constexpr const char* adapter_template = R"(// eomc simulate: C interface over one generated kernel.
#include "kernel.hpp"

#include <array>
#include <bit>
#include <cstddef>
#include <utility>

#include <eomc/runtime/kernel.hpp>
#include <experimental/simd>

namespace {
namespace rt = eomc::runtime;
using K = eomc::models::@STRUCT@;
using P = K::Parameters;
constexpr std::size_t n_par = K::n_parameters;

static_assert(rt::GeneratedKernel<K>, "eomc simulate: the header does not define a kernel of eomc's shape");
// Aggregate initialisation then fills the parameters by position, and their bytes are an array of doubles.
static_assert(rt::PositionalParameters<K>,
              "eomc simulate: Parameters must be a plain aggregate of exactly n_parameters doubles");

template <std::size_t... I>
P* create(const double* v, std::index_sequence<I...>) {
    (void)v;
    return new P{v[I]...};
}

// The optional parts (runtime/kernel.hpp): templates, so that the branch for a kernel without
// them is discarded.
template <class M>
void variational_rhs(double t, const double* y, double* dydt, const void* p) {
    if constexpr (rt::VariationalKernel<M>) M::template variational_rhs<double>(t, y, dydt, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)y, (void)dydt, (void)p;
}
template <class M>
void jacobian(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::KernelWithJacobian<M>) M::template jacobian<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
void project(double t, double* x, const void* p) {
    if constexpr (rt::ProjectingKernel<M>) M::template project<double>(t, x, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)p;
}

template <class M>
void acceleration(double t, const double* q, double* a, const void* p) {
    if constexpr (rt::SeparableKernel<M>) M::template acceleration<double>(t, q, a, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)q, (void)a, (void)p;
}
template <class M>
constexpr int n_events() {
    if constexpr (rt::EventKernel<M>) return M::n_events;
    else return 0;
}
template <class M>
const char* event_name(int i) {
    if constexpr (rt::EventKernel<M>) return M::event_names[std::size_t(i)];
    else return (void)i, nullptr;
}
template <class M>
int event_direction(int i) {
    if constexpr (rt::EventKernel<M>) return M::event_directions[std::size_t(i)];
    else return (void)i, 0;
}
template <class M>
int event_terminal(int i) {
    if constexpr (rt::EventKernel<M>) return M::event_terminal[std::size_t(i)] ? 1 : 0;
    else return (void)i, 0;
}
template <class M>
constexpr int n_constraints() {
    if constexpr (rt::ConstrainedKernel<M>) return M::n_constraints;
    else return 0;
}
template <class M>
const char* constraint_name(int i) {
    if constexpr (rt::ConstrainedKernel<M>) return M::constraint_names[std::size_t(i)];
    else return (void)i, nullptr;
}
template <class M>
void constraint_residuals(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::ConstrainedKernel<M>) M::template constraint_residuals<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
constexpr int n_programs() {
    if constexpr (rt::ProgramKernel<M>) return M::n_programs;
    else return 0;
}
template <class M>
const char* program_name(int i) {
    if constexpr (rt::ProgramKernel<M>) return M::program_names[std::size_t(i)];
    else return (void)i, nullptr;
}
template <class M>
double program_law(int i, int j) {
    if constexpr (rt::ProgramKernel<M>) return M::program_laws[std::size_t(4 * i + j)];
    else return (void)i, (void)j, 0.0;
}
template <class M>
void program_residuals(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::ProgramKernel<M>) M::template program_residuals<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
int constraint_holonomic(int i) {
    if constexpr (rt::ConstrainedKernel<M>) return M::constraint_holonomic[std::size_t(i)] ? 1 : 0;
    else return (void)i, 0;
}
template <class M>
int has_constraint_rows() {
    return rt::ContactConstrainedKernel<M> ? 1 : 0;
}
template <class M>
void constraint_rows(double t, const double* x, double* out, double* phi, double* W, double* r, const void* p) {
    if constexpr (rt::ContactConstrainedKernel<M>)
        M::template constraint_rows<double>(t, x, out, phi, W, r, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)phi, (void)W, (void)r, (void)p;
}
template <class M>
constexpr int n_singular_sets() {
    if constexpr (rt::SingularSetKernel<M>) return M::n_singular_sets;
    else return 0;
}
template <class M>
const char* singular_set_name(int i) {
    if constexpr (rt::SingularSetKernel<M>) return M::singular_set_names[std::size_t(i)];
    else return (void)i, nullptr;
}
template <class M>
int singular_set_order(int i) {
    if constexpr (rt::SingularSetKernel<M>) return M::singular_set_orders[std::size_t(i)];
    else return (void)i, 0;
}
template <class M>
void singular_sets(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::SingularSetKernel<M>) M::template singular_sets<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
constexpr int n_contacts() {
    if constexpr (rt::ContactKernel<M>) return M::n_contacts;
    else return 0;
}
template <class M>
const char* contact_name(int i) {
    if constexpr (rt::ContactKernel<M>) return M::contact_names[std::size_t(i)];
    else return (void)i, nullptr;
}
template <class M>
int contact_kinematic(int i) {
    if constexpr (rt::ContactKernel<M>) return M::contact_kinematic[std::size_t(i)] ? 1 : 0;
    else return (void)i, 0;
}
template <class M>
void restitutions(const void* p, double* out) {
    if constexpr (rt::ContactKernel<M>) M::template restitutions<double>(*static_cast<const typename M::Parameters*>(p), out);
    else (void)p, (void)out;
}
template <class M>
void gaps(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::ContactKernel<M>) M::template gaps<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
void contact_jacobian(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::ContactKernel<M>) M::template contact_jacobian<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
void contact_bias(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::ContactKernel<M>) M::template contact_bias<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
template <class M>
void contact_time_rates(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::MovingContactKernel<M>) {
        M::template contact_time_rates<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    } else {
        (void)t, (void)x, (void)p;
        for (int a = 0; a < n_contacts<M>(); ++a) out[a] = 0.0;  // fixed gaps: w = 0
    }
}

// A batchable kernel's rhs and invariants over batch_width members per call: S and the parameters'
// scalar a SIMD batch, one member per lane; the arrays lane-minor (a[i * batch_width + lane]).
// Templates on M = Basic<Name><Lanes>, so that nothing is instantiated for a kernel that is not
// K::batchable (its code solves or branches).
constexpr std::size_t batch_width = 4;  // two SSE2 registers of doubles
using Lanes = std::experimental::fixed_size_simd<double, batch_width>;
using BatchKernel = eomc::models::Basic@STRUCT@<Lanes>;
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
void rhs_batch(double t, const double* x, double* dxdt, const void* p) {
    if constexpr (K::batchable) {
        std::array<Lanes, K::n_state> xs, rates;
        for (std::size_t i = 0; i < xs.size(); ++i) xs[i].copy_from(x + i * batch_width, lane_minor);
        M::rhs(Lanes(t), xs.data(), rates.data(), *static_cast<const typename M::Parameters*>(p));
        for (std::size_t i = 0; i < xs.size(); ++i) rates[i].copy_to(dxdt + i * batch_width, lane_minor);
    } else {
        (void)t, (void)x, (void)dxdt, (void)p;
    }
}
template <class M>
void invariants_batch(double t, const double* x, double* out, const void* p) {
    if constexpr (K::batchable) {
        std::array<Lanes, K::n_state> xs;
        std::array<Lanes, K::n_invariants> values;
        for (std::size_t i = 0; i < xs.size(); ++i) xs[i].copy_from(x + i * batch_width, lane_minor);
        M::invariants(Lanes(t), xs.data(), values.data(), *static_cast<const typename M::Parameters*>(p));
        for (std::size_t i = 0; i < values.size(); ++i) values[i].copy_to(out + i * batch_width, lane_minor);
    } else {
        (void)t, (void)x, (void)out, (void)p;
    }
}

template <class M>
void events(double t, const double* x, double* out, const void* p) {
    if constexpr (rt::EventKernel<M>) M::template events<double>(t, x, out, *static_cast<const typename M::Parameters*>(p));
    else (void)t, (void)x, (void)out, (void)p;
}
}  // namespace

#define EOMC_EXPORT extern "C" __attribute__((visibility("default")))

EOMC_EXPORT int eomc_adapter_abi() { return @ABI@; }
// Which kernel this is: the struct and the SHA-256 of the header it was compiled from.
EOMC_EXPORT const char* eomc_kernel_identity() { return "@IDENTITY@"; }
EOMC_EXPORT const char* eomc_scene_name() { return K::scene_name; }
EOMC_EXPORT int eomc_n_state() { return K::n_state; }
EOMC_EXPORT int eomc_n_parameters() { return K::n_parameters; }
EOMC_EXPORT int eomc_n_invariants() { return K::n_invariants; }
EOMC_EXPORT int eomc_n_outputs() { return K::n_outputs; }
EOMC_EXPORT const char* const* eomc_state_names() { return K::state_names.data(); }
EOMC_EXPORT const char* const* eomc_parameter_names() { return K::parameter_names.data(); }
EOMC_EXPORT const char* const* eomc_invariant_names() { return K::invariant_names.data(); }
EOMC_EXPORT const char* const* eomc_output_names() { return K::output_names.data(); }
EOMC_EXPORT const double* eomc_initial_state() { return K::initial_state.data(); }

EOMC_EXPORT void eomc_parameter_defaults(double* out) {
    if constexpr (n_par > 0) {
        const auto values = std::bit_cast<std::array<double, n_par>>(P{});
        for (std::size_t i = 0; i < n_par; ++i) out[i] = values[i];
    } else {
        (void)out;
    }
}
EOMC_EXPORT void* eomc_create_parameters(const double* values) {
    return create(values, std::make_index_sequence<n_par>{});
}
EOMC_EXPORT void eomc_destroy_parameters(void* p) { delete static_cast<P*>(p); }

EOMC_EXPORT void eomc_rhs(double t, const double* x, double* dxdt, const void* p) {
    K::rhs<double>(t, x, dxdt, *static_cast<const P*>(p));
}
EOMC_EXPORT void eomc_invariants(double t, const double* x, double* out, const void* p) {
    K::invariants<double>(t, x, out, *static_cast<const P*>(p));
}
EOMC_EXPORT void eomc_outputs(double t, const double* x, double* out, const void* p) {
    K::outputs<double>(t, x, out, *static_cast<const P*>(p));
}

// The mechanical form M u̇ = f of the velocity block x[velocity_offset .. + n_velocities).
EOMC_EXPORT int eomc_n_coordinates() { return K::n_coordinates; }
EOMC_EXPORT int eomc_velocity_offset() { return K::velocity_offset; }
EOMC_EXPORT int eomc_n_velocities() { return K::n_velocities; }
EOMC_EXPORT void eomc_mass_matrix(double t, const double* x, double* out, const void* p) {
    K::mass_matrix<double>(t, x, out, *static_cast<const P*>(p));
}
EOMC_EXPORT void eomc_forcing(double t, const double* x, double* out, const void* p) {
    K::forcing<double>(t, x, out, *static_cast<const P*>(p));
}

EOMC_EXPORT int eomc_separable() { return rt::SeparableKernel<K> ? 1 : 0; }
EOMC_EXPORT int eomc_projects() { return rt::ProjectingKernel<K> ? 1 : 0; }
EOMC_EXPORT int eomc_variational() { return rt::VariationalKernel<K> ? 1 : 0; }
EOMC_EXPORT void eomc_variational_rhs(double t, const double* y, double* dydt, const void* p) {
    variational_rhs<K>(t, y, dydt, p);
}
EOMC_EXPORT int eomc_has_jacobian() { return rt::KernelWithJacobian<K> ? 1 : 0; }
EOMC_EXPORT void eomc_jacobian(double t, const double* x, double* out, const void* p) { jacobian<K>(t, x, out, p); }
EOMC_EXPORT void eomc_project(double t, double* x, const void* p) { project<K>(t, x, p); }
EOMC_EXPORT void eomc_acceleration(double t, const double* q, double* a, const void* p) { acceleration<K>(t, q, a, p); }
EOMC_EXPORT int eomc_n_events() { return n_events<K>(); }
EOMC_EXPORT const char* eomc_event_name(int i) { return event_name<K>(i); }
EOMC_EXPORT int eomc_event_direction(int i) { return event_direction<K>(i); }
EOMC_EXPORT int eomc_event_terminal(int i) { return event_terminal<K>(i); }
EOMC_EXPORT void eomc_events(double t, const double* x, double* out, const void* p) { events<K>(t, x, out, p); }
EOMC_EXPORT int eomc_n_constraints() { return n_constraints<K>(); }
EOMC_EXPORT const char* eomc_constraint_name(int i) { return constraint_name<K>(i); }
EOMC_EXPORT void eomc_constraint_residuals(double t, const double* x, double* out, const void* p) {
    constraint_residuals<K>(t, x, out, p);
}
EOMC_EXPORT int eomc_constraint_holonomic(int i) { return constraint_holonomic<K>(i); }
EOMC_EXPORT int eomc_has_constraint_rows() { return has_constraint_rows<K>(); }
EOMC_EXPORT void eomc_constraint_rows(double t, const double* x, double* out, double* phi, double* W, double* r,
                                      const void* p) {
    constraint_rows<K>(t, x, out, phi, W, r, p);
}
EOMC_EXPORT int eomc_n_contacts() { return n_contacts<K>(); }
EOMC_EXPORT const char* eomc_contact_name(int i) { return contact_name<K>(i); }
EOMC_EXPORT int eomc_contact_kinematic(int i) { return contact_kinematic<K>(i); }
EOMC_EXPORT void eomc_restitutions(const void* p, double* out) { restitutions<K>(p, out); }
EOMC_EXPORT void eomc_gaps(double t, const double* x, double* out, const void* p) { gaps<K>(t, x, out, p); }
EOMC_EXPORT void eomc_contact_jacobian(double t, const double* x, double* out, const void* p) {
    contact_jacobian<K>(t, x, out, p);
}
EOMC_EXPORT void eomc_contact_bias(double t, const double* x, double* out, const void* p) {
    contact_bias<K>(t, x, out, p);
}
EOMC_EXPORT int eomc_has_contact_time_rates() { return rt::MovingContactKernel<K> ? 1 : 0; }
EOMC_EXPORT void eomc_contact_time_rates(double t, const double* x, double* out, const void* p) {
    contact_time_rates<K>(t, x, out, p);
}
EOMC_EXPORT int eomc_n_programs() { return n_programs<K>(); }
EOMC_EXPORT const char* eomc_program_name(int i) { return program_name<K>(i); }
EOMC_EXPORT double eomc_program_law(int i, int j) { return program_law<K>(i, j); }
EOMC_EXPORT void eomc_program_residuals(double t, const double* x, double* out, const void* p) {
    program_residuals<K>(t, x, out, p);
}
// Batched members (0 lanes: the kernel is not batchable); parameters n_parameters × lanes.
EOMC_EXPORT int eomc_batch_width() { return K::batchable ? int(batch_width) : 0; }
EOMC_EXPORT void* eomc_create_batch_parameters(const double* values) {
    return create_batch<BatchKernel>(values, std::make_index_sequence<n_par>{});
}
EOMC_EXPORT void eomc_destroy_batch_parameters(void* p) { destroy_batch<BatchKernel>(p); }
EOMC_EXPORT void eomc_rhs_batch(double t, const double* x, double* dxdt, const void* p) {
    rhs_batch<BatchKernel>(t, x, dxdt, p);
}
EOMC_EXPORT void eomc_invariants_batch(double t, const double* x, double* out, const void* p) {
    invariants_batch<BatchKernel>(t, x, out, p);
}
EOMC_EXPORT int eomc_n_singular_sets() { return n_singular_sets<K>(); }
EOMC_EXPORT const char* eomc_singular_set_name(int i) { return singular_set_name<K>(i); }
EOMC_EXPORT int eomc_singular_set_order(int i) { return singular_set_order<K>(i); }
EOMC_EXPORT void eomc_singular_sets(double t, const double* x, double* out, const void* p) {
    singular_sets<K>(t, x, out, p);
}
)";

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

// The adapter and the kernel, built into a shared object with only the adapter's C functions
// exported (hidden visibility keeps the kernel's template instantiations out of the dynamic
// symbol table).
CompileRequest kernel_request(const std::string& header_text, const std::string& struct_name) {
    CompileRequest r;
    r.files = {{"adapter.cpp", adapter_source(struct_name, header_text)}, {"kernel.hpp", header_text}};
    r.flags = {"-fPIC", "-shared", "-fvisibility=hidden"};
    r.suffix = ".so";
    r.what = "the generated kernel";
    return r;
}

template <class F>
F symbol(void* handle, const char* name, const std::string& path) {
    void* p = ::dlsym(handle, name);
    if (!p) throw std::runtime_error(fmt::format("{}: no symbol {} (not an eomc kernel library)", path, name));
    return reinterpret_cast<F>(p);
}

std::vector<std::string> names(const char* const* array, int n) {
    return std::vector<std::string>(array, array + n);
}

}  // namespace

static std::string kernel_identity(const std::string& struct_name, const std::string& header_text) {
    return struct_name + " " + sha256_hex(header_text);
}

std::string adapter_source(const std::string& struct_name, const std::string& header_text) {
    if (!is_identifier(struct_name))
        throw std::runtime_error(fmt::format("'{}' is not a C++ identifier (expected the kernel's struct name)", struct_name));
    return replace_all(replace_all(replace_all(adapter_template, "@STRUCT@", struct_name), "@ABI@", std::to_string(adapter_abi)),
                       "@IDENTITY@", kernel_identity(struct_name, header_text));
}

std::string cache_key(const std::string& header_text, const std::string& struct_name) {
    return cache_key(kernel_request(header_text, struct_name));
}

KernelLibrary KernelLibrary::load(const std::string& header_text, const std::string& struct_name,
                                  const std::string& cache_dir) {
    const auto start = std::chrono::steady_clock::now();
    const CompileRequest request = kernel_request(header_text, struct_name);
    // Verified against its record before dlopen (which runs the object's initialisers and maps
    // its pages: a truncated file would SIGBUS later): a bad entry is rebuilt, never loaded.
    const Artifact artifact = find_or_compile(request, cache_dir);
    const fs::path path = artifact.path;

    KernelLibrary lib;
    lib.path_ = path.string();
    lib.cache_hit_ = artifact.cache_hit;
    // And once loaded, the kernel must say it is this one: the same struct, from the same header.
    const std::string identity = kernel_identity(struct_name, header_text);
    const auto identity_of = [&](void* handle) -> std::string {
        const auto abi = reinterpret_cast<int (*)()>(::dlsym(handle, "eomc_adapter_abi"));
        const auto id = reinterpret_cast<const char* (*)()>(::dlsym(handle, "eomc_kernel_identity"));
        if (!abi || !id) return "it is not an eomc kernel library";
        if (abi() != adapter_abi) return fmt::format("it has adapter interface {}, not {}", abi(), adapter_abi);
        return id() == identity ? "" : fmt::format("it is the kernel '{}', not '{}'", id(), identity);
    };
    lib.handle_ = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    std::string wrong = lib.handle_ ? identity_of(lib.handle_) : std::string(::dlerror());
    if (!wrong.empty() && lib.cache_hit_) {
        if (lib.handle_) ::dlclose(lib.handle_);
        lib.handle_ = nullptr;
        std::cerr << fmt::format("eomc: note: rebuilding {} cached as {}: {}\n", request.what, path.string(), wrong);
        compile(request, path);
        lib.cache_hit_ = false;
        lib.handle_ = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        wrong = lib.handle_ ? identity_of(lib.handle_) : std::string(::dlerror());
    }
    if (!wrong.empty()) throw std::runtime_error(fmt::format("cannot load the compiled kernel {}: {}", path.string(), wrong));

    void* h = lib.handle_;
    const std::string& p = lib.path_;
    lib.scene_name_ = symbol<const char* (*)()>(h, "eomc_scene_name", p)();
    const int n_state = symbol<int (*)()>(h, "eomc_n_state", p)();
    const int n_par = symbol<int (*)()>(h, "eomc_n_parameters", p)();
    const int n_inv = symbol<int (*)()>(h, "eomc_n_invariants", p)();
    const int n_out = symbol<int (*)()>(h, "eomc_n_outputs", p)();
    using Names = const char* const* (*)();
    lib.state_names_ = names(symbol<Names>(h, "eomc_state_names", p)(), n_state);
    lib.parameter_names_ = names(symbol<Names>(h, "eomc_parameter_names", p)(), n_par);
    lib.invariant_names_ = names(symbol<Names>(h, "eomc_invariant_names", p)(), n_inv);
    lib.output_names_ = names(symbol<Names>(h, "eomc_output_names", p)(), n_out);
    const double* x0 = symbol<const double* (*)()>(h, "eomc_initial_state", p)();
    lib.initial_state_.assign(x0, x0 + n_state);
    lib.parameter_defaults_.assign(static_cast<std::size_t>(n_par), 0.0);
    symbol<void (*)(double*)>(h, "eomc_parameter_defaults", p)(lib.parameter_defaults_.data());
    lib.create_parameters_ = symbol<void* (*)(const double*)>(h, "eomc_create_parameters", p);
    lib.destroy_parameters_ = symbol<void (*)(void*)>(h, "eomc_destroy_parameters", p);
    lib.rhs_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_rhs", p);
    lib.invariants_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_invariants", p);
    lib.outputs_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_outputs", p);
    lib.separable_ = symbol<int (*)()>(h, "eomc_separable", p)() != 0;
    lib.projects_ = symbol<int (*)()>(h, "eomc_projects", p)() != 0;
    lib.variational_ = symbol<int (*)()>(h, "eomc_variational", p)() != 0;
    lib.variational_rhs_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_variational_rhs", p);
    lib.has_jacobian_ = symbol<int (*)()>(h, "eomc_has_jacobian", p)() != 0;
    lib.jacobian_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_jacobian", p);
    lib.project_ = symbol<void (*)(double, double*, const void*)>(h, "eomc_project", p);
    lib.acceleration_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_acceleration", p);
    const int n_ev = symbol<int (*)()>(h, "eomc_n_events", p)();
    const auto event_name = symbol<const char* (*)(int)>(h, "eomc_event_name", p);
    const auto event_direction = symbol<int (*)(int)>(h, "eomc_event_direction", p);
    const auto event_terminal = symbol<int (*)(int)>(h, "eomc_event_terminal", p);
    for (int i = 0; i < n_ev; ++i) {
        lib.event_names_.emplace_back(event_name(i));
        lib.event_directions_.push_back(event_direction(i));
        lib.event_terminal_.push_back(event_terminal(i) != 0);
    }
    lib.events_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_events", p);
    const int n_con = symbol<int (*)()>(h, "eomc_n_constraints", p)();
    const auto constraint_name = symbol<const char* (*)(int)>(h, "eomc_constraint_name", p);
    const auto constraint_holonomic = symbol<int (*)(int)>(h, "eomc_constraint_holonomic", p);
    for (int i = 0; i < n_con; ++i) {
        lib.constraint_names_.emplace_back(constraint_name(i));
        lib.constraint_holonomic_.push_back(constraint_holonomic(i) != 0);
    }
    lib.constraint_residuals_ =
        symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_constraint_residuals", p);
    const int n_prog = symbol<int (*)()>(h, "eomc_n_programs", p)();
    const auto program_name = symbol<const char* (*)(int)>(h, "eomc_program_name", p);
    const auto program_law = symbol<double (*)(int, int)>(h, "eomc_program_law", p);
    for (int i = 0; i < n_prog; ++i) {
        lib.program_names_.emplace_back(program_name(i));
        lib.program_laws_.push_back({program_law(i, 0), program_law(i, 1), program_law(i, 2), program_law(i, 3)});
    }
    lib.program_residuals_ =
        symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_program_residuals", p);
    lib.has_constraint_rows_ = symbol<int (*)()>(h, "eomc_has_constraint_rows", p)() != 0;
    lib.constraint_rows_ = symbol<void (*)(double, const double*, double*, double*, double*, double*, const void*)>(
        h, "eomc_constraint_rows", p);
    const int n_sing = symbol<int (*)()>(h, "eomc_n_singular_sets", p)();
    const auto singular_set_name = symbol<const char* (*)(int)>(h, "eomc_singular_set_name", p);
    const auto singular_set_order = symbol<int (*)(int)>(h, "eomc_singular_set_order", p);
    for (int i = 0; i < n_sing; ++i) {
        lib.singular_set_names_.emplace_back(singular_set_name(i));
        lib.singular_set_orders_.push_back(singular_set_order(i));
    }
    lib.singular_sets_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_singular_sets", p);
    lib.batch_width_ = symbol<int (*)()>(h, "eomc_batch_width", p)();
    lib.create_batch_parameters_ = symbol<void* (*)(const double*)>(h, "eomc_create_batch_parameters", p);
    lib.destroy_batch_parameters_ = symbol<void (*)(void*)>(h, "eomc_destroy_batch_parameters", p);
    lib.rhs_batch_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_rhs_batch", p);
    lib.invariants_batch_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_invariants_batch", p);
    lib.n_coordinates_ = symbol<int (*)()>(h, "eomc_n_coordinates", p)();
    lib.velocity_offset_ = symbol<int (*)()>(h, "eomc_velocity_offset", p)();
    lib.n_velocities_ = symbol<int (*)()>(h, "eomc_n_velocities", p)();
    lib.mass_matrix_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_mass_matrix", p);
    lib.forcing_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_forcing", p);
    const int n_contacts = symbol<int (*)()>(h, "eomc_n_contacts", p)();
    const auto contact_name = symbol<const char* (*)(int)>(h, "eomc_contact_name", p);
    const auto contact_kinematic = symbol<int (*)(int)>(h, "eomc_contact_kinematic", p);
    for (int i = 0; i < n_contacts; ++i) {
        lib.contact_names_.emplace_back(contact_name(i));
        lib.contact_kinematic_.push_back(contact_kinematic(i) != 0);
    }
    lib.restitutions_ = symbol<void (*)(const void*, double*)>(h, "eomc_restitutions", p);
    lib.gaps_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_gaps", p);
    lib.contact_jacobian_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_contact_jacobian", p);
    lib.contact_bias_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_contact_bias", p);
    lib.moving_contacts_ = symbol<int (*)()>(h, "eomc_has_contact_time_rates", p)() != 0;
    lib.contact_time_rates_ =
        symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_contact_time_rates", p);
    lib.seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return lib;
}

KernelLibrary::Parameters KernelLibrary::make_parameters(const std::vector<double>& values) const {
    if (values.size() != parameter_names_.size())
        throw std::invalid_argument(fmt::format("make_parameters: {} values for {} parameters", values.size(),
                                                parameter_names_.size()));
    return Parameters(create_parameters_(values.data()), ParameterDeleter{destroy_parameters_});
}

KernelLibrary::Parameters KernelLibrary::make_batch_parameters(const std::vector<double>& values) const {
    const std::size_t lanes = static_cast<std::size_t>(batch_width_);
    if (lanes == 0) throw std::logic_error(fmt::format("make_batch_parameters: the kernel {} is not batchable", scene_name_));
    if (values.size() != parameter_names_.size() * lanes)
        throw std::invalid_argument(fmt::format("make_batch_parameters: {} values for {} parameters × {} lanes",
                                                values.size(), parameter_names_.size(), lanes));
    return Parameters(create_batch_parameters_(values.data()), ParameterDeleter{destroy_batch_parameters_});
}

KernelLibrary::KernelLibrary(KernelLibrary&& other) noexcept { *this = std::move(other); }

KernelLibrary& KernelLibrary::operator=(KernelLibrary&& other) noexcept {
    if (this != &other) {
        close();
        handle_ = std::exchange(other.handle_, nullptr);
        path_ = std::move(other.path_);
        cache_hit_ = other.cache_hit_;
        seconds_ = other.seconds_;
        scene_name_ = std::move(other.scene_name_);
        state_names_ = std::move(other.state_names_);
        parameter_names_ = std::move(other.parameter_names_);
        invariant_names_ = std::move(other.invariant_names_);
        output_names_ = std::move(other.output_names_);
        initial_state_ = std::move(other.initial_state_);
        parameter_defaults_ = std::move(other.parameter_defaults_);
        create_parameters_ = other.create_parameters_;
        destroy_parameters_ = other.destroy_parameters_;
        rhs_ = other.rhs_;
        invariants_ = other.invariants_;
        outputs_ = other.outputs_;
        separable_ = other.separable_;
        projects_ = other.projects_;
        variational_ = other.variational_;
        variational_rhs_ = other.variational_rhs_;
        has_jacobian_ = other.has_jacobian_;
        jacobian_ = other.jacobian_;
        project_ = other.project_;
        acceleration_ = other.acceleration_;
        event_names_ = std::move(other.event_names_);
        event_directions_ = std::move(other.event_directions_);
        event_terminal_ = std::move(other.event_terminal_);
        events_ = other.events_;
        constraint_names_ = std::move(other.constraint_names_);
        constraint_residuals_ = other.constraint_residuals_;
        constraint_holonomic_ = std::move(other.constraint_holonomic_);
        has_constraint_rows_ = other.has_constraint_rows_;
        constraint_rows_ = other.constraint_rows_;
        singular_set_names_ = std::move(other.singular_set_names_);
        singular_set_orders_ = std::move(other.singular_set_orders_);
        singular_sets_ = other.singular_sets_;
        program_names_ = std::move(other.program_names_);
        program_laws_ = std::move(other.program_laws_);
        program_residuals_ = other.program_residuals_;
        n_coordinates_ = other.n_coordinates_;
        velocity_offset_ = other.velocity_offset_;
        n_velocities_ = other.n_velocities_;
        mass_matrix_ = other.mass_matrix_;
        forcing_ = other.forcing_;
        contact_names_ = std::move(other.contact_names_);
        contact_kinematic_ = std::move(other.contact_kinematic_);
        restitutions_ = other.restitutions_;
        gaps_ = other.gaps_;
        contact_jacobian_ = other.contact_jacobian_;
        contact_bias_ = other.contact_bias_;
        moving_contacts_ = other.moving_contacts_;
        contact_time_rates_ = other.contact_time_rates_;
        batch_width_ = other.batch_width_;
        create_batch_parameters_ = other.create_batch_parameters_;
        destroy_batch_parameters_ = other.destroy_batch_parameters_;
        rhs_batch_ = other.rhs_batch_;
        invariants_batch_ = other.invariants_batch_;
    }
    return *this;
}

KernelLibrary::~KernelLibrary() { close(); }

void KernelLibrary::close() {
    if (handle_) ::dlclose(handle_);
    handle_ = nullptr;
}

}  // namespace eomc::host
