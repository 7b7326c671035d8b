// Turns an emitted kernel header into code running in this process: a small C adapter is
// compiled with the system C++ compiler into a shared object, cached by content, and loaded
// with dlopen. The generated header stays the only description of the model; nothing here
// parses it.
#pragma once

#include <cstddef>
#include <memory>
#include <array>
#include <string>
#include <vector>

#include "host/toolchain.hpp"

namespace eomc::host {

// One compiled kernel, loaded. Move-only; unloads the library when destroyed, so nothing
// obtained from it (parameter blocks included) may outlive it.
class KernelLibrary {
public:
    // Compiles (or finds in `cache_dir`, "" = default_cache_dir()) the shared object for the
    // kernel struct eomc::models::<struct_name> defined by `header_text`, and loads it.
    // The compiler is the one that built eomc unless $EOMC_CXX names another (part of the
    // cache key either way). Throws std::runtime_error with the compiler's output when
    // compilation fails.
    static KernelLibrary load(const std::string& header_text, const std::string& struct_name,
                              const std::string& cache_dir = "");

    KernelLibrary(KernelLibrary&&) noexcept;
    KernelLibrary& operator=(KernelLibrary&&) noexcept;
    ~KernelLibrary();

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
    void rhs(double t, const double* x, double* dxdt, const Parameters& p) const { rhs_(t, x, dxdt, p.get()); }
    void invariants(double t, const double* x, double* out, const Parameters& p) const {
        invariants_(t, x, out, p.get());
    }

    // Quantities written beside the state (a free carrier's reactions), n_outputs doubles.
    void outputs(double t, const double* x, double* out, const Parameters& p) const { outputs_(t, x, out, p.get()); }

    // Kernels generated with --variational: the rates of y = (x, Φ), Φ row-major n_state × n_state.
    bool variational() const { return variational_; }
    void variational_rhs(double t, const double* y, double* dydt, const Parameters& p) const {
        variational_rhs_(t, y, dydt, p.get());
    }

    // ∂ẋ/∂x at (t, x), row-major n_state × n_state (the implicit radau5's Newton iteration); only
    // when has_jacobian(): a kernel generated without its Jacobian has none.
    bool has_jacobian() const { return has_jacobian_; }
    void jacobian(double t, const double* x, double* out, const Parameters& p) const { jacobian_(t, x, out, p.get()); }

    // After an accepted step at time t, in place: kernels whose state holds a unit quaternion (a
    // free carrier's attitude) put it back on |e| = 1, encke kernels rectify their reference
    // orbit when the deviation has grown; project() does nothing for the others.
    bool projects() const { return projects_; }
    void project(double t, double* x, const Parameters& p) const { project_(t, x, p.get()); }

    // q̈ = a(t, q) for separable systems (the splitting methods): q and a of n_coordinates =
    // n_state / 2 doubles. Only when separable(); otherwise the kernel has no acceleration().
    bool separable() const { return separable_; }
    void acceleration(double t, const double* q, double* a, const Parameters& p) const { acceleration_(t, q, a, p.get()); }

    // The scene's events: g_i(t, x) written to out[0 .. event_names().size()); directions +1 (up
    // only), -1 (down only), 0 (both).
    const std::vector<std::string>& event_names() const { return event_names_; }
    const std::vector<int>& event_directions() const { return event_directions_; }
    const std::vector<bool>& event_terminal() const { return event_terminal_; }
    void events(double t, const double* x, double* out, const Parameters& p) const { events_(t, x, out, p.get()); }

    // Bilateral constraint rows (none for most kernels): one residual per row, f(q, t) for a
    // holonomic row and φ(q, u, t) for a kinematic one, written to out[0 .. constraint_names().size()).
    const std::vector<std::string>& constraint_names() const { return constraint_names_; }
    void constraint_residuals(double t, const double* x, double* out, const Parameters& p) const {
        constraint_residuals_(t, x, out, p.get());
    }
    const std::vector<bool>& constraint_holonomic() const { return constraint_holonomic_; }
    // Kernels with bilateral and unilateral rows (runtime/kernel.hpp, ContactConstrainedKernel): the
    // residuals (f or φ), φ, W (constraint_names().size() × n_velocities(), row-major) and r of W u̇ = r.
    bool has_constraint_rows() const { return has_constraint_rows_; }
    void constraint_rows(double t, const double* x, double* out, double* phi, double* W, double* r,
                         const Parameters& p) const {
        constraint_rows_(t, x, out, phi, W, r, p.get());
    }

    // Programs realised by controls (none for most kernels; Mei ch. 3): each one's law
    // {configuration 1 or 0, α, β, κ} (gains 0: the open loop) and residuals, two per program (ω and
    // ω̇, or φ and 0), written to out[0 .. 2 program_names().size()).
    const std::vector<std::string>& program_names() const { return program_names_; }
    const std::vector<std::array<double, 4>>& program_laws() const { return program_laws_; }
    void program_residuals(double t, const double* x, double* out, const Parameters& p) const {
        program_residuals_(t, x, out, p.get());
    }

    // Where the mass matrix is singular (none for most kernels): indicators s_k(t, x) of the sets
    // s_k = 0 ("sin(theta) = 0"), each with its power in det M, written to out[0 .. singular_set_names().size()).
    const std::vector<std::string>& singular_set_names() const { return singular_set_names_; }
    const std::vector<int>& singular_set_orders() const { return singular_set_orders_; }
    void singular_sets(double t, const double* x, double* out, const Parameters& p) const {
        singular_sets_(t, x, out, p.get());
    }

    // The mechanical form M(t, x) u̇ = f(t, x) of the velocity block x[velocity_offset() ..
    // velocity_offset() + n_velocities()): M row-major n_velocities², f n_velocities doubles.
    int n_coordinates() const { return n_coordinates_; }
    int velocity_offset() const { return velocity_offset_; }
    int n_velocities() const { return n_velocities_; }
    void mass_matrix(double t, const double* x, double* out, const Parameters& p) const {
        mass_matrix_(t, x, out, p.get());
    }
    void forcing(double t, const double* x, double* out, const Parameters& p) const { forcing_(t, x, out, p.get()); }

    // Unilateral rows (none for most kernels; runtime/kernel.hpp, ContactKernel): names, which are
    // kinematic (velocity level), Newton's restitutions from the parameters, the gaps (f, or φ for a
    // kinematic row), W (contact_names().size() × n_velocities(), row-major) and the bias of
    // f̈ = W u̇ + bias.
    const std::vector<std::string>& contact_names() const { return contact_names_; }
    const std::vector<bool>& contact_kinematic() const { return contact_kinematic_; }
    void restitutions(const Parameters& p, double* out) const { restitutions_(p.get(), out); }
    void gaps(double t, const double* x, double* out, const Parameters& p) const { gaps_(t, x, out, p.get()); }
    void contact_jacobian(double t, const double* x, double* out, const Parameters& p) const {
        contact_jacobian_(t, x, out, p.get());
    }
    void contact_bias(double t, const double* x, double* out, const Parameters& p) const {
        contact_bias_(t, x, out, p.get());
    }
    // w = ∂f/∂t per row (ḟ = W u + w); zeros for a kernel whose gaps do not move (moving_contacts()).
    bool moving_contacts() const { return moving_contacts_; }
    void contact_time_rates(double t, const double* x, double* out, const Parameters& p) const {
        contact_time_rates_(t, x, out, p.get());
    }

    // How the library was obtained.
    const std::string& library_path() const { return path_; }
    bool cache_hit() const { return cache_hit_; }
    double seconds() const { return seconds_; }  // compiling (or finding) and loading

private:
    KernelLibrary() = default;
    void close();

    void* handle_ = nullptr;
    std::string path_;
    bool cache_hit_ = false;
    double seconds_ = 0.0;

    std::string scene_name_;
    std::vector<std::string> state_names_, parameter_names_, invariant_names_, output_names_;
    std::vector<double> initial_state_, parameter_defaults_;
    void* (*create_parameters_)(const double*) = nullptr;
    void (*destroy_parameters_)(void*) = nullptr;
    void (*rhs_)(double, const double*, double*, const void*) = nullptr;
    void (*invariants_)(double, const double*, double*, const void*) = nullptr;
    void (*outputs_)(double, const double*, double*, const void*) = nullptr;
    bool separable_ = false;
    bool projects_ = false;
    bool variational_ = false;
    void (*variational_rhs_)(double, const double*, double*, const void*) = nullptr;
    void (*project_)(double, double*, const void*) = nullptr;
    void (*acceleration_)(double, const double*, double*, const void*) = nullptr;
    std::vector<std::string> event_names_;
    std::vector<int> event_directions_;
    std::vector<bool> event_terminal_;
    void (*events_)(double, const double*, double*, const void*) = nullptr;
    std::vector<std::string> constraint_names_;
    void (*constraint_residuals_)(double, const double*, double*, const void*) = nullptr;
    std::vector<std::string> program_names_;
    std::vector<std::array<double, 4>> program_laws_;
    void (*program_residuals_)(double, const double*, double*, const void*) = nullptr;
    std::vector<bool> constraint_holonomic_;
    bool has_constraint_rows_ = false;
    void (*constraint_rows_)(double, const double*, double*, double*, double*, double*, const void*) = nullptr;
    std::vector<std::string> singular_set_names_;
    std::vector<int> singular_set_orders_;
    void (*singular_sets_)(double, const double*, double*, const void*) = nullptr;
    int n_coordinates_ = 0, velocity_offset_ = 0, n_velocities_ = 0;
    void (*mass_matrix_)(double, const double*, double*, const void*) = nullptr;
    void (*forcing_)(double, const double*, double*, const void*) = nullptr;
    std::vector<std::string> contact_names_;
    std::vector<bool> contact_kinematic_;
    void (*restitutions_)(const void*, double*) = nullptr;
    void (*gaps_)(double, const double*, double*, const void*) = nullptr;
    void (*contact_jacobian_)(double, const double*, double*, const void*) = nullptr;
    void (*contact_bias_)(double, const double*, double*, const void*) = nullptr;
    bool moving_contacts_ = false;
    void (*contact_time_rates_)(double, const double*, double*, const void*) = nullptr;
    bool has_jacobian_ = false;
    void (*jacobian_)(double, const double*, double*, const void*) = nullptr;
};

// Exposed for tests: the adapter source for a struct and its header (it exports the kernel's
// identity, "<struct> <SHA-256 of the header>", checked after loading), and the cache key of a
// header compiled with it by the configured compiler and flags.
std::string adapter_source(const std::string& struct_name, const std::string& header_text);
std::string cache_key(const std::string& header_text, const std::string& struct_name);

}  // namespace eomc::host
