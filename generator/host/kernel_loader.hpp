// Turns an emitted kernel header into code running in this process: a small C adapter is
// compiled with the system C++ compiler into a shared object, cached by content, and loaded
// with dlopen. The generated header stays the only description of the model; nothing here
// parses it.
#pragma once

#include <cstddef>
#include <memory>
#include <array>
#include <string>
#include <type_traits>
#include <vector>

#include "eomc/runtime/kernel/c_interface.hpp"
#include "host/toolchain.hpp"

namespace eomc::host {

// A column of blocks.def as the loader holds it: one value per row, or an array of `width`.
template <class T, int width>
using ColumnOf = std::conditional_t<width == 1, std::vector<T>, std::vector<std::array<T, width>>>;

// One compiled kernel, loaded. Move-only; unloads the library when destroyed, so nothing
// obtained from it (parameter blocks included) may outlive it.
class KernelLibrary {
public:
    // Compiles (or finds in `cache_dir`, "" = default_cache_dir()) the shared object for the
    // kernel struct eomc::models::<struct_name> defined by `header_text`, and loads it.
    // The compiler is the one that built eomc unless $EOMC_CXX names another (part of the
    // cache key either way), targeting this machine's instructions (-march=native where the
    // compiler accepts it, the CPU it describes in the key; $EOMC_PORTABLE=1: portable code).
    // With `batch` the library also has the SIMD batch of a batchable kernel (batch_width() > 0;
    // a separate cache entry, four times the compile); without it, batch_width() is 0. Throws
    // std::runtime_error with the compiler's output when compilation fails.
    static KernelLibrary load(const std::string& header_text, const std::string& struct_name,
                              const std::string& cache_dir = "", bool batch = false);

    KernelLibrary(KernelLibrary&&) noexcept = default;
    KernelLibrary& operator=(KernelLibrary&&) noexcept = default;

    const std::string& scene_name() const { return scene_name_; }
    const std::vector<std::string>& state_names() const { return state_names_; }
    const std::vector<std::string>& parameter_names() const { return parameter_names_; }
    const std::vector<std::string>& invariant_names() const { return invariant_names_; }
    const std::vector<std::string>& output_names() const { return output_names_; }
    const std::vector<double>& initial_state() const { return initial_state_; }
    const std::vector<double>& parameter_defaults() const { return parameter_defaults_; }

    // The kernel's Parameters struct, built from values in parameter_names() order.
    struct ParameterDeleter {
        void (*destroy)(void*) = nullptr;
        void operator()(void* p) const { destroy(p); }
    };
    using Parameters = std::unique_ptr<void, ParameterDeleter>;
    Parameters make_parameters(const std::vector<double>& values) const;

    // ẋ = rhs(t, x) and the invariants, over arrays of n_state / n_invariants doubles.
    void rhs(double t, const double* x, double* dxdt, const Parameters& p) const { vt_.rhs(t, x, dxdt, p.get()); }
    void invariants(double t, const double* x, double* out, const Parameters& p) const {
        vt_.invariants(t, x, out, p.get());
    }

    // Quantities written beside the state (a free carrier's reactions), n_outputs doubles.
    void outputs(double t, const double* x, double* out, const Parameters& p) const { vt_.outputs(t, x, out, p.get()); }

    // The mechanical form M(t, x) u̇ = f(t, x) of the velocity block x[velocity_offset() ..
    // velocity_offset() + n_velocities()): M row-major n_velocities², f n_velocities doubles.
    int n_coordinates() const { return vt_.n_coordinates; }
    int velocity_offset() const { return vt_.velocity_offset; }
    int n_velocities() const { return vt_.n_velocities; }
    void mass_matrix(double t, const double* x, double* out, const Parameters& p) const {
        vt_.mass_matrix(t, x, out, p.get());
    }
    void forcing(double t, const double* x, double* out, const Parameters& p) const { vt_.forcing(t, x, out, p.get()); }

    // The optional blocks, one accessor per row of eomc/runtime/kernel/blocks.def (which says
    // what each block is): names() for a group of rows, column() for a column (a vector of one
    // value per row, or of an std::array of `width`), and for a function
    //   void name(<its shape>, const Parameters& p) const;   e.g. gaps(t, x, out, p)
    //   bool has_name() const;                               the kernel has the block
    // A kernel without a block has no rows, and its functions write nothing (or zeros, where the
    // row says so). tests/host/kernel_library_interface.cpp lists every accessor's signature.
#define EOMC_KERNEL_ROWS(concept, count, names) \
    const std::vector<std::string>& names() const { return names##_; }
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width) \
    const ColumnOf<type, width>& column() const { return column##_; }
#define EOMC_KERNEL_FUNCTION(concept, name, shape)                                                   \
    bool has_##name() const { return vt_.has_##name; }                                               \
    void name(EOMC_KERNEL_SHAPE_##shape(const Parameters&)) const { vt_.name(EOMC_KERNEL_CALL_##shape(p.get())); }
#include "eomc/runtime/kernel/blocks.def"

    // The blocks' flags under the names the simulation knew them by.
    bool variational() const { return has_variational_rhs(); }  // generated with --variational
    bool projects() const { return has_project(); }
    bool separable() const { return has_acceleration(); }  // otherwise the kernel has no acceleration()
    bool moving_contacts() const { return has_contact_time_rates(); }

    // Batchable kernels loaded with `batch` (straight-line rates; 0 otherwise): rhs and invariants
    // of batch_width() members per call, each a lane of a SIMD batch with its own parameters. Arrays
    // are lane-minor, a[i * batch_width() + lane]; the parameters' values n_parameters ×
    // batch_width(), lane-minor.
    int batch_width() const { return vt_.batch_width; }
    Parameters make_batch_parameters(const std::vector<double>& values) const;
    void rhs_batch(double t, const double* x, double* dxdt, const Parameters& p) const {
        vt_.rhs_batch(t, x, dxdt, p.get());
    }
    void invariants_batch(double t, const double* x, double* out, const Parameters& p) const {
        vt_.invariants_batch(t, x, out, p.get());
    }

    // How the library was obtained.
    const std::string& library_path() const { return path_; }
    bool cache_hit() const { return cache_hit_; }
    double seconds() const { return seconds_; }  // compiling (or finding) and loading

private:
    KernelLibrary() = default;
    // The steps of load(): open the library and check it is the kernel (rebuilding a cached one
    // that is not), then copy its tables out.
    void open(const CompileRequest& request, const std::string& identity);
    std::string open_checked(const std::string& identity);  // why it is not the kernel, "" when it is
    void read_kernel();
    void read_blocks();

    struct Unload {
        void operator()(void* handle) const;
    };
    std::unique_ptr<void, Unload> handle_;  // first, so that it is unloaded last
    runtime::kernel_c::VTable vt_{};
    std::string path_;
    bool cache_hit_ = false;
    double seconds_ = 0.0;

    std::string scene_name_;
    std::vector<std::string> state_names_, parameter_names_, invariant_names_, output_names_;
    std::vector<double> initial_state_, parameter_defaults_;
#define EOMC_KERNEL_ROWS(concept, count, names) std::vector<std::string> names##_;
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width) ColumnOf<type, width> column##_;
#include "eomc/runtime/kernel/blocks.def"
};

// What the loader compiles for a header: the adapter (templates/kernel_adapter.cpp) told the
// kernel's struct and identity, "<struct> <SHA-256 of the header>", which it exports and the
// loader checks once loaded. Exposed for tests, with the cache key of that request.
CompileRequest kernel_request(const std::string& header_text, const std::string& struct_name, bool batch = false);
std::string cache_key(const std::string& header_text, const std::string& struct_name, bool batch = false);

}  // namespace eomc::host
