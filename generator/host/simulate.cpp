#include "host/simulate.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <filesystem>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "eomc/runtime/runtime.hpp"
#include "host/kernel_loader.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"
#include "support/json.hpp"
#include "support/output_file.hpp"

namespace eomc::host {

namespace {

using Clock = std::chrono::steady_clock;
using runtime::State;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

// Everything that can be checked before compiling, so that a typo costs no compile.
void validate(const SimulationRequest& r) {
    if (!scene::is_integrator(r.integrator)) {
        const std::vector<std::string> names(scene::integrator_names.begin(), scene::integrator_names.end());
        const std::string near = nearest_name(r.integrator, names);
        throw InputError(SourcePos{"--integrator"}, fmt::format("unknown integrator '{}'{} (expected one of {})",
                                                                r.integrator,
                                                                near.empty() ? "" : "; did you mean '" + near + "'?",
                                                                join(names)));
    }
    const bool fixed = scene::is_fixed_step(r.integrator);
    if (!(std::isfinite(r.t_end) && r.t_end > 0.0))
        throw InputError(SourcePos{"--t-end"}, fmt::format("the end time must be positive and finite, not {}", r.t_end));
    if (fixed && !(std::isfinite(r.step) && r.step > 0.0))
        throw InputError(SourcePos{"--step"}, fmt::format("the {} step must be positive and finite, not {}",
                                                          r.integrator, r.step));
    if (!fixed) {
        if (!(r.rtol >= 0.0 && r.atol >= 0.0 && (r.rtol > 0.0 || r.atol > 0.0) && std::isfinite(r.rtol) &&
              std::isfinite(r.atol)))
            throw InputError(SourcePos{"--rtol"}, fmt::format("tolerances must be finite, non-negative and not both zero "
                                                              "(rtol {}, atol {})", r.rtol, r.atol));
    }
    if (r.max_steps && *r.max_steps == 0)
        throw InputError(SourcePos{"--max-steps"}, "the step budget must be at least 1");
    if (fixed) {
        // Known before the run: refuse it now rather than after hours, or after a disk is full.
        const double steps = std::ceil(r.t_end / r.step);
        const std::size_t budget = r.max_steps.value_or(SimulationRequest::default_max_fixed_steps);
        if (steps > static_cast<double>(budget))
            throw InputError(SourcePos{"--step"},
                             fmt::format("{} with step {} to t_end = {} takes {:.3g} steps, more than the budget of {} "
                                         "(--max-steps); take a larger step or a shorter run, or raise --max-steps",
                                         r.integrator, r.step, r.t_end, steps, budget));
        if (!r.csv_path.empty() && steps + 1.0 > static_cast<double>(r.max_rows))
            throw InputError(SourcePos{"--output"},
                             fmt::format("the CSV {} would hold {:.3g} rows (one per step), more than the limit of {} "
                                         "(--max-rows); take a larger step or a shorter run, or raise --max-rows",
                                         r.csv_path, steps + 1.0, r.max_rows));
    }
    if (r.summary_format != "text" && r.summary_format != "json")
        throw InputError(SourcePos{"--summary"},
                         fmt::format("unknown summary format '{}' (expected text or json)", r.summary_format));
}

// --set NAME=VALUE: a parameter, or the initial value of a state component ("q", "q_dot").
void apply_overrides(const SimulationRequest& r, const KernelLibrary& lib, std::vector<double>& parameters,
                     State<double>& x) {
    const SourcePos where{"--set"};
    for (const auto& [name, value] : r.overrides) {
        const auto find = [&](const std::vector<std::string>& names) {
            for (std::size_t i = 0; i < names.size(); ++i)
                if (names[i] == name) return static_cast<std::ptrdiff_t>(i);
            return std::ptrdiff_t{-1};
        };
        const std::ptrdiff_t p = find(lib.parameter_names()), s = find(lib.state_names());
        if (p < 0 && s < 0) {
            std::vector<std::string> known = lib.parameter_names();
            known.insert(known.end(), lib.state_names().begin(), lib.state_names().end());
            const std::string near = nearest_name(name, known);
            throw InputError(where, fmt::format("'{}' is neither a parameter nor a state variable of {}{} "
                                                "(parameters: {}; initial values: {})",
                                                name, lib.scene_name(), near.empty() ? "" : "; did you mean '" + near + "'?",
                                                join(lib.parameter_names()), join(lib.state_names())));
        }
        if (p >= 0 && s >= 0)
            throw InputError(where, fmt::format("'{}' names both a parameter and a state variable", name));
        if (!std::isfinite(value)) throw InputError(where, fmt::format("{}={}: the value must be finite", name, value));
        (p >= 0 ? parameters[static_cast<std::size_t>(p)] : x[static_cast<std::size_t>(s)]) = value;
    }
}

// The CSV goes to a temporary file next to the target and is renamed over it when the run ends:
// after a successful integration, or after one that failed mid-run (a collision, a step-size
// collapse), when it holds every row up to the last accepted state. A run that fails in any other
// way (bad input, an I/O error, the row limit, a signal) leaves neither a half-written file nor a
// clobbered old one (cli/output_file.hpp: what may be replaced, and how).
class CsvOutput {
public:
    CsvOutput(const std::string& path, const std::vector<std::string>& columns, std::size_t max_rows)
        : max_rows_(max_rows) {
        if (path.empty()) return;
        out_.emplace(path);  // refuses a target that is not a regular file now, not after a long run
        file_ = out_->stream();
        std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
        std::string header;
        for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
        header += '\n';
        std::fwrite(header.data(), 1, header.size(), file_);
    }
    CsvOutput(const CsvOutput&) = delete;
    CsvOutput& operator=(const CsvOutput&) = delete;

    // `event`: the name of the event located at t, or null; with_event_column: the CSV has one.
    // Throws RowLimit before writing row max_rows + 1.
    // `extra`: cells after the outputs, each behind its comma (a contact run's λ and active set).
    void row(double t, const State<double>& x, const std::vector<double>& invariants, const std::vector<double>& outputs,
             const std::string* event = nullptr, bool with_event_column = false, std::string_view extra = {}) {
        if (!file_) return;
        if (rows_ >= max_rows_) throw RowLimit(t);
        buffer_.clear();
        fmt::format_to(std::back_inserter(buffer_), "{:.17g}", t);
        for (double v : x) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
        for (double v : invariants) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
        for (double v : outputs) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
        buffer_.append(extra.data(), extra.data() + extra.size());
        if (with_event_column) {
            buffer_.push_back(',');
            if (event) buffer_.append(event->data(), event->data() + event->size());
        }
        buffer_.push_back('\n');
        std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
        ++rows_;
    }

    // Flushes, syncs, closes and renames into place; throws (and removes the temporary) on any I/O error.
    void commit() {
        if (!file_) return;
        file_ = nullptr;
        out_->commit();
    }

    std::size_t rows() const { return rows_; }

    struct RowLimit {
        double t;
    };

private:
    std::optional<AtomicOutput> out_;
    std::FILE* file_ = nullptr;
    fmt::memory_buffer buffer_;
    std::size_t rows_ = 0, max_rows_;
};

// A one-line bar on stderr, for people watching a terminal: silent for runs under ~1 s,
// redrawn at most 10 times a second, erased when done (also when the run fails).
class ProgressBar {
public:
    ProgressBar(bool wanted, double t_end) : enabled_(wanted && ::isatty(STDERR_FILENO)), t_end_(t_end) {}
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;
    ~ProgressBar() {
        if (drawn_) std::fputs("\r\033[K", stderr);
    }

    void update(double t) {
        // Reading the clock every step would cost more than a small kernel's step.
        if (!enabled_ || (++calls_ & 63u) != 0) return;
        const auto now = Clock::now();
        if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        const double fraction = std::clamp(t / t_end_, 0.0, 1.0);
        constexpr int width = 30;
        const int filled = static_cast<int>(fraction * width);
        std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.6g / %.6g", std::string(filled, '#').c_str(),
                     std::string(width - filled, ' ').c_str(), static_cast<int>(fraction * 100), t, t_end_);
        std::fflush(stderr);
        drawn_ = true;
    }

private:
    bool enabled_;
    double t_end_;
    Clock::time_point start_ = Clock::now(), last_{};
    unsigned calls_ = 0;
    bool drawn_ = false;
};

// max |I(t) − I(0)| over the observed points; a NaN drift sticks, so it is reported, not hidden.
double track_max(double current_max, double drift) {
    if (std::isnan(current_max)) return current_max;
    return std::isnan(drift) || drift > current_max ? drift : current_max;
}

std::string number(double v) { return fmt::format("{:.17g}", v); }

std::string json_number(double v) { return std::isfinite(v) ? number(v) : "null"; }

}  // namespace

void check_separable(const std::string& integrator, const SourcePos& where, bool separable,
                     const std::string& scene_name) {
    if (scene::is_splitting(integrator) && !separable)
        throw InputError(where, fmt::format("the {} integrator needs a separable system (q̈ = a(t, q) with a constant "
                                            "mass matrix, forces free of the velocities), and {} is not one; use gl4, "
                                            "gl6 or gl8 for a symplectic fixed-step method",
                                            integrator, scene_name));
}

double InvariantReport::relative_drift() const {
    return initial != 0.0 ? max_abs_drift / std::abs(initial) : std::numeric_limits<double>::quiet_NaN();
}

double SimulationResult::value(const std::string& name) const {
    for (const auto& [n, v] : state)
        if (n == name) return v;
    for (const auto& [n, v] : outputs)
        if (n == name) return v;
    for (const auto& c : contacts)
        if ("lambda_" + c.name == name) return c.lambda;
    throw std::out_of_range("no state variable or output '" + name + "'");
}

// An orbit kernel's re_entry event (g = r − radius, downwards) cannot see a start already below
// the surface: the generator refuses such a scene, and this refuses a --set that moves the start
// (or the radius) there.
void refuse_start_below_surface(const SimulationRequest& r, const KernelLibrary& lib,
                                const KernelLibrary::Parameters& parameters, const State<double>& x) {
    const auto& names = lib.event_names();
    const auto it = std::find(names.begin(), names.end(), "re_entry");
    if (it == names.end() || r.overrides.empty()) return;
    std::vector<double> g(names.size());
    lib.events(0.0, x.data(), g.data(), parameters);
    const double height = g[static_cast<std::size_t>(it - names.begin())];
    if (!(height > 0))
        throw InputError(SourcePos{"--set"},
                         fmt::format("the initial state of {} is {} km below the central body's surface "
                                     "(r − radius = {}): the run would start re-entered",
                                     lib.scene_name(), number(-height), number(height)));
}

namespace {

// The run's description for the summary: the method with its step or tolerances.
std::string describe_method(const SimulationRequest& request, bool compensated) {
    return scene::is_fixed_step(request.integrator)
               ? fmt::format("{} (step {}{})", request.integrator, request.step, compensated ? ", compensated" : "")
               : fmt::format("{} (rtol {}, atol {}{})", request.integrator, request.rtol, request.atol,
                             compensated ? ", compensated" : "");
}

// The variational run extends the state by Φ, starting from the identity, and names its entries.
void extend_by_transition_matrix(const SimulationRequest& request, const KernelLibrary& lib, State<double>& x,
                                 std::vector<std::string>& state_names) {
    if (!lib.variational()) throw std::runtime_error("the kernel has no variational_rhs: generate it with --variational");
    if (scene::is_splitting(request.integrator))
        throw InputError(request.integrator_pos,
                         fmt::format("the {} integrator steps q and q̇ by the acceleration alone and cannot carry "
                                     "the variational equations; use rk4, gl4, gl6, gl8, dopri5 or dop853",
                                     request.integrator));
    const std::size_t n = x.size();
    x.resize(n + n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        x[n + i * n + i] = 1.0;
        for (std::size_t j = 0; j < n; ++j) state_names.push_back(fmt::format("Phi_{}_{}", i, j));
    }
}

// The kernel as a runtime system. One whose state holds a unit quaternion puts it back on
// |e| = 1 after every step, an encke kernel rectifies its reference orbit (runtime::Projecting);
// for the others project() changes nothing, and an unchanged state costs the steppers nothing.
struct KernelSystem {
    const KernelLibrary& lib;
    const KernelLibrary::Parameters& parameters;
    bool variational;
    void operator()(double t, const State<double>& xs, State<double>& dxdt) const {
        if (variational) lib.variational_rhs(t, xs.data(), dxdt.data(), parameters);
        else lib.rhs(t, xs.data(), dxdt.data(), parameters);
    }
    void project(double t, State<double>& xs) const {
        if (lib.projects()) lib.project(t, xs.data(), parameters);
    }
};

// The kernel with its Jacobian ∂ẋ/∂x, for the implicit radau5 (runtime::HasJacobian); only
// over the plain state (a variational run's Φ block has no kernel Jacobian: differenced there).
struct KernelJacobianSystem : KernelSystem {
    mutable std::vector<double> buffer;
    void jacobian(double t, const State<double>& xs, Eigen::MatrixXd& J) const {
        const Eigen::Index n = J.rows();
        buffer.resize(std::size_t(n * n));
        lib.jacobian(t, xs.data(), buffer.data(), parameters);
        for (Eigen::Index i = 0; i < n; ++i)
            for (Eigen::Index j = 0; j < n; ++j) J(i, j) = buffer[std::size_t(i * n + j)];
    }
};

// Whether radau5 gets the kernel's symbolic Jacobian (else forward differences, n calls each):
// not for the variational state, nor for the contact phases (their rates carry the multipliers).
bool symbolic_jacobian(const SimulationRequest& request, const KernelLibrary& lib) {
    return lib.has_jacobian() && !request.variational && lib.contact_names().empty();
}

// Which Jacobian radau5 runs on, for the summary.
std::string jacobian_source(const SimulationRequest& request, const KernelLibrary& lib) {
    if (symbolic_jacobian(request, lib)) return "the kernel's symbolic Jacobian";
    if (request.variational) return "finite-difference Jacobian: the variational state has none";
    if (!lib.contact_names().empty()) return "finite-difference Jacobian: the contact phases' rates have none";
    return "finite-difference Jacobian: the kernel was generated without one";
}

// The stiffness hint for the explicit adaptive methods: a run is stability-limited when its
// accepted steps sit at the method's stability boundary, h |λ| ≈ the boundary for the fastest
// decaying eigenvalue λ of ∂ẋ/∂x, step after step (the test of Hairer's dopri5.f and dop853.f,
// after Shampine; [HW] E. Hairer, G. Wanner, Solving ODEs II, Sect. IV.2). Here λ comes from the
// kernel's Jacobian, sampled every few accepted steps; 15 samples at 70 % of the boundary or more
// make the hint, as 15 detections do in those codes, when they are at least half of the samples
// (a run stability-limited for most of its length).
class StiffnessWatch {
public:
    StiffnessWatch(const SimulationRequest& request, const KernelLibrary& lib, const KernelLibrary::Parameters& p)
        : lib_(lib), parameters_(p), boundary_(stability_boundary(request.integrator)) {
        if (!lib.has_jacobian() || request.variational) boundary_ = 0.0;
        const std::size_t n = lib.state_names().size();
        every_ = std::max<std::size_t>(1, n * n / 16);  // the O(n³) eigenvalues cost about what n² / 16 steps do
        buffer_.resize(n * n);
    }

    // After each accepted step from t_old to t.
    void step(double t_old, double t, const State<double>& xs) {
        if (boundary_ <= 0.0 || ++steps_ % every_ != 0) return;
        const Eigen::Index n = Eigen::Index(xs.size());
        lib_.jacobian(t, xs.data(), buffer_.data(), parameters_);
        const Eigen::MatrixXd J = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            buffer_.data(), n, n);
        if (!J.allFinite()) return;
        const Eigen::EigenSolver<Eigen::MatrixXd> eig(J, false);
        double rho = 0.0;  // the largest |λ| with Re λ < 0
        for (Eigen::Index i = 0; i < n; ++i)
            if (eig.eigenvalues()[i].real() < 0.0) rho = std::max(rho, std::abs(eig.eigenvalues()[i]));
        ++samples_;
        const double hl = std::abs(t - t_old) * rho;
        if (hl >= 0.7 * boundary_) {
            ++at_boundary_;
            max_hl_ = std::max(max_hl_, hl);
        }
    }

    // "" unless the run was stability-limited.
    std::string hint(const std::string& integrator) const {
        if (at_boundary_ < 15 || 2 * at_boundary_ < samples_) return "";
        return fmt::format("{} of {} sampled steps sit at {}'s stability boundary (h |λ| up to {:.3g}, boundary {:.3g}): "
                           "the system is stiff and the step is limited by stability, not accuracy; try --integrator "
                           "radau5",
                           at_boundary_, samples_, integrator, max_hl_, boundary_);
    }

private:
    // Where the real axis leaves the stability region, as dopri5.f (3.25) and dop853.f (6.1) test it.
    static double stability_boundary(const std::string& name) {
        if (name == "dopri5") return 3.25;
        if (name == "dop853") return 6.1;
        return 0.0;
    }
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    double boundary_;
    std::size_t every_ = 1, steps_ = 0, samples_ = 0, at_boundary_ = 0;
    double max_hl_ = 0.0;
    std::vector<double> buffer_;
};

// The request's method over [0, t_end] from x (advanced in place), with the kernel's events.
template <class Observer, class OnEvent>
runtime::EventOutcome<double> integrate(const SimulationRequest& request, bool compensated, const KernelSystem& system,
                                        State<double>& x, runtime::EventLocator<double>& locator, Observer&& observer,
                                        OnEvent&& on_event) {
    const KernelLibrary& lib = system.lib;
    KernelSystem sys = system;  // the drivers take the system by reference
    auto acceleration = [&](double t, const State<double>& q, State<double>& a) {
        lib.acceleration(t, q.data(), a.data(), system.parameters);
    };
    auto event_functions = [&](double t, const State<double>& xs, State<double>& g) {
        lib.events(t, xs.data(), g.data(), system.parameters);
    };
    auto fixed_step = [&](auto&& stepper, auto& f) {
        // The step count is the user's choice here, not a sign of no progress: the budget must
        // not stop a long fixed-step run short of t_end. validate() bounded it by max_steps;
        // the two spare attempts are the runtime's (a last partial step, an event re-step).
        runtime::Limits limits;
        const double steps = std::ceil(request.t_end / request.step) + 2.0;
        limits.max_steps = std::max(limits.max_steps, static_cast<std::size_t>(steps));
        return runtime::integrate_fixed_events(stepper, f, x, 0.0, request.t_end, request.step, locator,
                                               event_functions, observer, on_event, limits);
    };
    auto adaptive = [&](auto&& stepper) {
        stepper.set_compensated(compensated);
        runtime::Limits limits;
        if (request.max_steps) limits.max_steps = *request.max_steps;
        return runtime::integrate_adaptive_events(stepper, sys, x, 0.0, request.t_end, 0.0,
                                                  runtime::Tolerances{request.rtol, request.atol}, locator,
                                                  event_functions, observer, on_event, limits);
    };
    runtime::GaussLegendreOptions gauss;
    gauss.compensated = compensated;
    runtime::SplittingOptions splitting;
    splitting.compensated = compensated;
    // The stepper named in the request, through the runtime's registry (validate() checked the
    // name); each kind takes its own options.
    return runtime::visit_integrator<double>(request.integrator, [&](auto tag) {
        using Tag = decltype(tag);
        using Stepper = typename Tag::type;
        if constexpr (Tag::info.uses_jacobian) {
            if (symbolic_jacobian(request, lib)) {
                KernelJacobianSystem jsys{sys, {}};
                runtime::Limits limits;
                if (request.max_steps) limits.max_steps = *request.max_steps;
                Stepper stepper;
                stepper.set_compensated(compensated);
                return runtime::integrate_adaptive_events(stepper, jsys, x, 0.0, request.t_end, 0.0,
                                                          runtime::Tolerances{request.rtol, request.atol}, locator,
                                                          event_functions, observer, on_event, limits);
            }
            return adaptive(Stepper{});
        } else if constexpr (Tag::info.kind == runtime::IntegratorKind::adaptive) {
            return adaptive(Stepper{});
        } else if constexpr (Tag::info.needs_separable) {
            return fixed_step(Stepper{splitting}, acceleration);
        } else if constexpr (Tag::info.kind == runtime::IntegratorKind::implicit) {
            return fixed_step(Stepper{gauss}, sys);
        } else {
            Stepper stepper;
            stepper.set_compensated(compensated);
            return fixed_step(stepper, sys);
        }
    });
}

// Which variable failed and where the solution was last seen; the rows up to there are a valid
// trajectory, kept for the post-mortem.
runtime::IntegrationError failed_run(const runtime::IntegrationError& e, const SimulationRequest& request,
                                     const std::string& scene_name, const std::vector<std::string>& state_names,
                                     double t_last, const State<double>& x_last, CsvOutput& csv) {
    std::string message = fmt::format("simulating {} with {}: {}", scene_name, request.integrator, e.what());
    if (e.component() < state_names.size())
        message += fmt::format("; component {} is {}", e.component(), state_names[e.component()]);
    message += fmt::format("; last accepted state at t = {}:", number(t_last));
    for (std::size_t i = 0; i < x_last.size(); ++i) message += fmt::format(" {} = {}", state_names[i], number(x_last[i]));
    if (!request.csv_path.empty()) {
        csv.commit();
        message += fmt::format("; {} holds the {} rows up to t = {}", request.csv_path, csv.rows(), number(t_last));
    }
    return runtime::IntegrationError(e.kind(), e.t(), message, e.component());
}

// The sets where the kernel's mass matrix is singular (gimbal lock): after every accepted step
// (and at t0) each indicator s_k must stay clear of zero. Near a set whose indicator divides
// det M to the power m, the smallest eigenvalue of M shrinks like |s_k|^m while the others stay,
// so cond(M) ≈ cond₀ (scale/|s_k|)^m with scale the size of |s_k| away from the set (the largest
// |s_k| seen so far). Past cond(M) = 1/√ε the solve of M u̇ = f keeps fewer than half of the
// digits: the run stops when |s_k| < ε^(1/2m) · scale, or when s_k changed sign between two
// accepted steps (the step went through the set), before any non-finite value is written.
class SingularSetWatch {
public:
    SingularSetWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
        : lib_(lib), parameters_(parameters), value_(lib.singular_set_names().size()),
          previous_(value_.size(), 0.0), scale_(value_.size(), 0.0) {}

    // Throws IntegrationError(singular_set) naming the set the state at t has reached.
    void check(double t, const State<double>& xs) {
        if (value_.empty()) return;
        lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
        for (std::size_t k = 0; k < value_.size(); ++k) {
            const double s = value_[k];
            const int order = std::max(1, lib_.singular_set_orders()[k]);
            const double threshold =
                std::pow(std::numeric_limits<double>::epsilon(), 0.5 / order) * std::max(scale_[k], std::abs(s));
            const bool crossed = seen_ && std::isfinite(s) && s * previous_[k] < 0.0;
            if (!std::isfinite(s) || std::abs(s) <= threshold || crossed) fail(t, k, s, threshold, crossed);
            scale_[k] = std::max(scale_[k], std::abs(s));
            previous_[k] = s;
        }
        seen_ = true;
    }

    // The indicators at x (for the message of a run that failed otherwise), "" when none is near.
    std::string near(double t, const State<double>& xs) {
        if (value_.empty()) return "";
        lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
        std::string out;
        for (std::size_t k = 0; k < value_.size(); ++k)
            if (scale_[k] > 0 && std::abs(value_[k]) < 1e-2 * scale_[k])
                out += fmt::format("; the last accepted state is near the singular set {} of the mass matrix "
                                   "(indicator {:.3g}, {:.3g} of its scale)",
                                   lib_.singular_set_names()[k], value_[k], std::abs(value_[k]) / scale_[k]);
        return out;
    }

    // A run that failed otherwise (the step collapsed, a value overflowed) next to the set where a
    // program's control matrix Ā M⁻¹ D is singular (|det| below 1e-6 of its scale, where the
    // control λ ~ 1/det has grown a millionfold) failed because of it: throws that reason instead.
    void fail_if_near_control_set(double t, const State<double>& xs) {
        if (value_.empty()) return;
        lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
        for (std::size_t k = 0; k < value_.size(); ++k)
            if (lib_.singular_set_names()[k].rfind("det(A M^-1 D)", 0) == 0 && scale_[k] > 0 &&
                std::abs(value_[k]) < 1e-6 * scale_[k])
                fail(t, k, value_[k], 1e-6 * scale_[k], false);
    }

private:
    [[noreturn]] void fail(double t, std::size_t k, double s, double threshold, bool crossed) const {
        const std::string& name = lib_.singular_set_names()[k];
        if (name.rfind("det(A M^-1 D)", 0) == 0)  // a program's control matrix (Mei ch. 3), not M
            throw runtime::IntegrationError(
                runtime::IntegrationError::Kind::singular_set, t,
                fmt::format("the programs cannot be realised past t = {}: the control matrix A M^-1 D became singular "
                            "({}); no control in the given directions keeps the programs there (eomc control prints "
                            "the singular set)",
                            number(t),
                            crossed ? fmt::format("det changed sign from {:.3g} to {:.3g} in one step", previous_[k], s)
                                    : fmt::format("|det| = {:.3g} fell below {:.3g} of its scale {:.3g}",
                                                  std::abs(s), threshold, std::max(scale_[k], std::abs(s)))));
        throw runtime::IntegrationError(
            runtime::IntegrationError::Kind::singular_set, t,
            fmt::format("the state reached the singular set {} of the mass matrix ({}: det M = 0 there, the "
                        "coordinates fail) at t = {}: {}; use coordinates without this singularity (or start away "
                        "from it)",
                        name,
                        name.find("sin(") != std::string::npos || name.find("cos(") != std::string::npos
                            ? "gimbal lock"
                            : "a coordinate singularity",
                        number(t),
                        crossed ? fmt::format("the indicator changed sign from {:.3g} to {:.3g} in one step",
                                              previous_[k], s)
                                : fmt::format("|{}| = {:.3g} fell below {:.3g} = eps^(1/{}) of its scale {:.3g}, where "
                                              "cond(M) would pass 1/sqrt(eps)",
                                              name.substr(0, name.rfind(" = 0")), std::abs(s), threshold, 2 * std::max(1, lib_.singular_set_orders()[k]),
                                              std::max(scale_[k], std::abs(s)))));
    }

    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> value_, previous_, scale_;
    bool seen_ = false;
};


// The kernel's programs (Mei ch. 3): at every observed point the residuals, and their departure
// from Erugin's closed-form law started from the residuals at t0 (runtime/program/erugin.hpp).
class ProgramWatch {
public:
    explicit ProgramWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
        : lib_(lib), parameters_(parameters), value_(2 * lib.program_names().size()) {
        for (std::size_t i = 0; i < lib.program_names().size(); ++i) {
            ProgramReport r;
            r.name = lib.program_names()[i];
            const auto& law = lib.program_laws()[i];
            const bool configuration = law[0] != 0.0, open = law[1] == 0.0 && law[2] == 0.0 && law[3] == 0.0;
            r.law = open ? (configuration ? "omega_ddot = 0 (open loop)" : "phi_dot = 0 (open loop)")
                    : configuration ? fmt::format("omega_ddot + {} omega_dot + {} omega = 0", number(2 * law[1]),
                                                  number(law[2] * law[2]))
                                    : fmt::format("phi_dot + {} phi = 0", number(law[3]));
            reports_.push_back(std::move(r));
        }
    }

    void observe(double t, const State<double>& xs) {
        if (reports_.empty()) return;
        lib_.program_residuals(t, xs.data(), value_.data(), parameters_);
        if (!started_) t0_ = t;
        for (std::size_t i = 0; i < reports_.size(); ++i) {
            ProgramReport& r = reports_[i];
            const auto& law = lib_.program_laws()[i];
            const double w = value_[2 * i], wd = value_[2 * i + 1];
            if (!started_) r.initial = w, r.initial_rate = wd;
            const double expected =
                law[0] != 0.0 ? runtime::program::erugin_configuration(law[1], law[2], r.initial, r.initial_rate, t - t0_)
                              : runtime::program::erugin_phase(law[3], r.initial, t - t0_);
            r.final = w;
            r.max_abs_residual = track_max(r.max_abs_residual, std::abs(w));
            r.max_departure = track_max(r.max_departure, std::abs(w - expected));
        }
        started_ = true;
    }

    std::vector<ProgramReport> reports() const { return reports_; }

private:
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> value_;
    std::vector<ProgramReport> reports_;
    bool started_ = false;
    double t0_ = 0.0;
};

// ---------------------------------------------------------------------------------------
// Kernels with unilateral rows (Mei, Special Topics in Analytical Mechanics, ch. 6): the event-driven
// hybrid driver (runtime/contact/event_driven.hpp) or Moreau–Jean time stepping (runtime/contact/
// moreau_jean.hpp; V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical Systems,
// Springer 2008). The CSV gains lambda_<row> per row and `active`, the active set as a bitmask
// (bit α, value 2^α, set when row α is in the active set: 0 in free flight, 1 for a single row
// in contact), and the event column labels the rows written at transitions impact:<row>,
// contact:<row>, separation:<row>, zeno:<row> (one row per event, the state after the transition).

const char* contact_kind_name(runtime::contact::ContactEventKind kind) {
    switch (kind) {
        case runtime::contact::ContactEventKind::impact: return "impact";
        case runtime::contact::ContactEventKind::contact: return "contact";
        case runtime::contact::ContactEventKind::separation: return "separation";
        case runtime::contact::ContactEventKind::zeno: return "zeno";
    }
    return "?";
}

// The drivers assume q̇ = u (W = ∂f/∂q acts on the velocities, the impact law on q̇): the kernel's
// velocity block must follow its coordinates, as many, and its coordinate rates must be those
// velocities. The last is probed at the start state and at a shifted one with distinct velocities:
// a kernel with q̇ = u writes the rate as a copy of the velocity (exact), one with quasi-velocities
// (q̇ = A(q) u) does not.
void require_rates_are_velocities(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters,
                                  const State<double>& x0) {
    const int n = lib.n_coordinates(), nu = lib.n_velocities(), N = int(x0.size());
    const SourcePos where{"[[unilateral]]"};
    if (nu != n || lib.velocity_offset() != n || N != 2 * n)
        throw InputError(where, fmt::format("{}: unilateral rows need the velocity block to be q̇ (the state (q, q̇) with "
                                            "n_velocities = velocity_offset = n_coordinates); this kernel has {} "
                                            "coordinates, {} velocities at offset {} in {} state variables",
                                            lib.scene_name(), n, nu, lib.velocity_offset(), N));
    State<double> x = x0, dxdt(x0.size());
    for (int probe = 0; probe < 2; ++probe) {
        for (int k = 0; k < n; ++k) {
            if (probe == 1) x[std::size_t(k)] = x0[std::size_t(k)] + 0.125 * (k + 1);
            x[std::size_t(n + k)] = 0.375 + 0.25 * k + 0.5 * probe;
        }
        lib.rhs(0.0, x.data(), dxdt.data(), parameters);
        for (int k = 0; k < n; ++k) {
            const double u = x[std::size_t(n + k)], rate = dxdt[std::size_t(k)];
            if (!(std::abs(rate - u) <= 8 * std::numeric_limits<double>::epsilon() * std::abs(u)))
                throw InputError(where, fmt::format("{}: unilateral rows need q̇ = u, but the rate of {} is not the "
                                                    "velocity {} (at {} = {} the kernel gives {} = {}): the velocities "
                                                    "are quasi-velocities, which the contact drivers do not take",
                                                    lib.scene_name(), lib.state_names()[std::size_t(k)],
                                                    lib.state_names()[std::size_t(n + k)],
                                                    lib.state_names()[std::size_t(n + k)], number(u),
                                                    lib.state_names()[std::size_t(k)] + "_rate", number(rate)));
        }
    }
}

SimulationResult simulate_contacts(const SimulationRequest& request, const KernelLibrary& lib,
                                   const KernelLibrary::Parameters& parameters, State<double>& x,
                                   SimulationResult result) {
    using Vector = runtime::contact::Vector<double>;
    using Matrix = runtime::contact::Matrix<double>;
    const std::string& scene = lib.scene_name();
    const std::size_t m = lib.contact_names().size();
    const bool event_driven = request.contact_method == "event_driven";
    if (!event_driven && request.contact_method != "moreau_jean")
        throw InputError(request.contact_method_pos, fmt::format("unknown contact method '{}' (expected event_driven "
                                                                 "or moreau_jean)", request.contact_method));
    const SourcePos rows_pos{"[[unilateral]]"};
    const std::size_t k_rows = lib.constraint_names().size();
    if (k_rows > 0 && !lib.has_constraint_rows())
        throw InputError(rows_pos, fmt::format("{}: the kernel has bilateral rows ({}) beside unilateral ones but no "
                                               "constraint_rows(); regenerate it with this eomc",
                                               scene, join(lib.constraint_names())));
    const std::size_t n_ev = lib.event_names().size();
    if (n_ev > 0 && !event_driven)
        throw InputError(request.contact_method_pos,
                         fmt::format("{}: scene events ({}) together with unilateral rows need contact method "
                                     "event_driven; moreau_jean does not locate them yet",
                                     scene, join(lib.event_names())));
    if (request.variational)
        throw InputError(SourcePos{"--variational"}, fmt::format("{}: the state-transition matrix is not defined "
                                                                 "across impacts; run without --variational", scene));
    if (m > 64)
        throw InputError(rows_pos, fmt::format("{}: {} unilateral rows; the CSV's active-set bitmask holds 64", scene, m));
    require_rates_are_velocities(lib, parameters, x);
    const int n = lib.n_coordinates();
    std::vector<double> restitution(m);
    lib.restitutions(parameters, restitution.data());
    for (std::size_t a = 0; a < m; ++a)
        if (!(restitution[a] >= 0.0 && restitution[a] <= 1.0))
            throw InputError(rows_pos, fmt::format("{}: the restitution of {} is {}, outside [0, 1]", scene,
                                                   lib.contact_names()[a], number(restitution[a])));
    std::vector<double> g0(m);
    lib.gaps(0.0, x.data(), g0.data(), parameters);
    for (std::size_t a = 0; a < m; ++a) {
        const double slack = request.atol + 1e-12 * (1.0 + std::abs(x[0]));
        if (!(g0[a] >= -slack))
            throw InputError(rows_pos, fmt::format("{}: the initial state violates the unilateral row {}: {} = {} < 0",
                                                   scene, lib.contact_names()[a],
                                                   lib.contact_kinematic()[a] ? "phi" : "f", number(g0[a])));
    }
    const bool sequential = request.impact_law == "sequential";
    if (!sequential && request.impact_law != "simultaneous")
        throw InputError(request.impact_law_pos, fmt::format("unknown impact law '{}' (expected simultaneous or "
                                                             "sequential)", request.impact_law));
    if (!event_driven && sequential)
        throw InputError(request.impact_law_pos, fmt::format("{}: the sequential impact law needs contact method "
                                                             "event_driven; Moreau-Jean resolves every step's impacts "
                                                             "simultaneously", scene));
    if (!event_driven) {
        if (!(std::isfinite(request.step) && request.step > 0.0))
            throw InputError(SourcePos{"--step"}, fmt::format("the moreau_jean step must be positive and finite, not {}",
                                                              request.step));
        if (!(request.theta >= 0.0 && request.theta <= 1.0))
            throw InputError(request.contact_method_pos, fmt::format("theta must lie in [0, 1], not {}", request.theta));
        const double steps = std::ceil(request.t_end / request.step);
        const std::size_t budget = request.max_steps.value_or(SimulationRequest::default_max_fixed_steps);
        if (steps > static_cast<double>(budget))
            throw InputError(SourcePos{"--step"}, fmt::format("moreau_jean with step {} to t_end = {} takes {:.3g} steps, "
                                                              "more than the budget of {} (--max-steps)",
                                                              request.step, request.t_end, steps, budget));
    } else {
        bool ok = false;
        runtime::visit_integrator<double>(request.integrator, [&](auto tag) {
            using Tag = decltype(tag);
            ok = Tag::info.kind == runtime::IntegratorKind::adaptive && Tag::info.dense_output;
            return 0;
        });
        if (!ok)
            throw InputError(request.integrator_pos,
                             fmt::format("{}: the event-driven contact method needs an adaptive integrator with dense "
                                         "output (dopri5 or dop853), not {}; or use contact method moreau_jean",
                                         scene, request.integrator));
    }
    result.contact_method = request.contact_method;
    result.impact_law = request.impact_law;
    if (!event_driven)
        result.integrator = fmt::format("moreau_jean (theta = {}, step {})", number(request.theta), number(request.step));
    for (std::size_t a = 0; a < m; ++a)
        result.contacts.push_back({lib.contact_names()[a], lib.contact_kinematic()[a], restitution[a], 0.0, false, 0});

    const std::vector<std::string>& state_names = lib.state_names();
    const std::size_t n_inv = lib.invariant_names().size();
    std::vector<std::string> columns{"t"};
    columns.insert(columns.end(), state_names.begin(), state_names.end());
    columns.insert(columns.end(), lib.invariant_names().begin(), lib.invariant_names().end());
    columns.insert(columns.end(), lib.output_names().begin(), lib.output_names().end());
    for (const auto& name : lib.contact_names()) columns.push_back("lambda_" + name);
    columns.push_back("active");
    columns.push_back("event");
    CsvOutput csv(request.csv_path, columns, request.max_rows);
    std::vector<double> outputs(lib.output_names().size()), inv(n_inv), inv0(n_inv), max_drift(n_inv, 0.0);
    bool first = true;
    double t_last = 0.0;
    State<double> x_last = x;
    ProgressBar progress(request.progress, request.t_end);
    std::vector<double> lambda_now(m, 0.0);
    std::vector<bool> active_now(m, false);
    std::string extra, label;
    // One CSV row per contact event at t (the state after its transition), or one labelled with the
    // scene event `scene_event`, or one plain row.
    auto record = [&](double t, const State<double>& xs, const std::vector<ContactEventReport>& events,
                      const std::string* scene_event = nullptr) {
        lib.invariants(t, xs.data(), inv.data(), parameters);
        if (first) inv0 = inv, first = false;
        for (std::size_t i = 0; i < n_inv; ++i) max_drift[i] = track_max(max_drift[i], std::abs(inv[i] - inv0[i]));
        if (!outputs.empty() && !request.csv_path.empty()) lib.outputs(t, xs.data(), outputs.data(), parameters);
        std::uint64_t bits = 0;
        extra.clear();
        for (std::size_t a = 0; a < m; ++a) {
            extra += fmt::format(",{:.17g}", lambda_now[a]);
            if (active_now[a]) bits |= std::uint64_t(1) << a;
        }
        extra += fmt::format(",{}", bits);
        if (scene_event) csv.row(t, xs, inv, outputs, scene_event, true, extra);
        else if (events.empty()) csv.row(t, xs, inv, outputs, nullptr, true, extra);
        for (const auto& e : events) {
            label = e.kind + ":" + e.name;
            csv.row(t, xs, inv, outputs, &label, true, extra);
        }
        t_last = t;
        x_last = xs;
        progress.update(t);
    };
    // The bilateral rows (Mei §6.6: a nonholonomic system with unilateral holonomic constraints), always
    // active in both drivers: at a state xs their residuals f, φ, W (here C, k × n) and r of C u̇ = r.
    const int k = int(k_rows);
    std::vector<double> rows_buffer(k_rows * std::size_t(n) + 1), mass_buffer(std::size_t(n * n));
    const auto bilateral_at = [&](double t, const double* xs, Vector& f, Vector& phi, Matrix& C, Vector& r) {
        f.resize(k);
        phi.resize(k);
        r.resize(k);
        C.resize(k, n);
        lib.constraint_rows(t, xs, f.data(), phi.data(), rows_buffer.data(), r.data(), parameters);
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < n; ++j) C(i, j) = rows_buffer[std::size_t(i * n + j)];
    };
    // Puts xs on every bilateral row, positions then velocities, in the M-metric (HLW IV.4).
    std::unique_ptr<bool[]> all_rows(new bool[k_rows + 1]), holonomic_rows(new bool[k_rows + 1]);
    for (std::size_t i = 0; i < k_rows; ++i) {
        all_rows[i] = true;
        holonomic_rows[i] = lib.constraint_holonomic()[i];
    }
    const auto project_bilateral = [&](double t, double* xs) {
        if (k == 0) return;
        std::vector<double> r(k_rows);
        runtime::project_onto_constraints<double>(
            t, xs, runtime::ConstraintLayout{n, n, n, k}, all_rows.get(), holonomic_rows.get(),
            [&](double tau, const double* y, double* f, double* phi) {
                lib.constraint_rows(tau, y, f, phi, rows_buffer.data(), r.data(), parameters);
            },
            [&](double tau, const double* y, double* W) {
                std::vector<double> f(k_rows), phi(k_rows);
                lib.constraint_rows(tau, y, f.data(), phi.data(), W, r.data(), parameters);
            },
            [&](double tau, const double* y, double* M) { lib.mass_matrix(tau, y, M, parameters); });
    };

    std::vector<ContactEventReport> pending;
    const auto add_event = [&](ContactEventReport e) {
        if (e.kind == "impact") {
            for (auto& c : result.contacts)
                if (c.name == e.name) ++c.impacts;
        }
        result.contact_events.push_back(e);
        pending.push_back(std::move(e));
    };

    const auto start = Clock::now();
    try {
        if (event_driven) {
            runtime::contact::ContactSystem<double> sys;
            sys.dof = n;
            for (std::size_t a = 0; a < m; ++a)
                sys.contacts.push_back({restitution[a], lib.contact_kinematic()[a] ? runtime::contact::GapLevel::velocity
                                                                                   : runtime::contact::GapLevel::position});
            sys.bilateral_holonomic = lib.constraint_holonomic();
            State<double> scratch(x.size(), 0.0);
            std::vector<double> buffer(std::size_t(std::max<std::size_t>(m, 1) * std::size_t(n) + std::size_t(n * n)));
            const auto put = [&](const Vector& q, const Vector* u) {
                for (int k = 0; k < n; ++k) {
                    scratch[std::size_t(k)] = q[k];
                    scratch[std::size_t(n + k)] = u ? (*u)[k] : 0.0;
                }
            };
            sys.mass = [&](double t, const Vector& q, Matrix& M) {
                put(q, nullptr);
                lib.mass_matrix(t, scratch.data(), buffer.data(), parameters);
                for (int i = 0; i < n; ++i)
                    for (int j = 0; j < n; ++j) M(i, j) = buffer[std::size_t(i * n + j)];
            };
            sys.force = [&](double t, const Vector& q, const Vector& u, Vector& f) {
                put(q, &u);
                lib.forcing(t, scratch.data(), f.data(), parameters);
            };
            sys.gaps = [&](double t, const Vector& q, const Vector& u, Vector& g) {
                put(q, &u);
                lib.gaps(t, scratch.data(), g.data(), parameters);
            };
            sys.rows = [&](double t, const Vector& q, const Vector& u, Matrix& W, Vector& b) {
                put(q, &u);
                lib.contact_jacobian(t, scratch.data(), buffer.data(), parameters);
                for (std::size_t a = 0; a < m; ++a)
                    for (int k = 0; k < n; ++k) W(Eigen::Index(a), k) = buffer[a * std::size_t(n) + std::size_t(k)];
                lib.contact_bias(t, scratch.data(), b.data(), parameters);
            };
            // Moving gaps: ḟ = W u + w, w = ∂f/∂t (fixed gaps leave it out: w = 0).
            if (lib.moving_contacts())
                sys.time_rates = [&](double t, const Vector& q, Vector& w) {
                    put(q, nullptr);
                    lib.contact_time_rates(t, scratch.data(), w.data(), parameters);
                };
            if (k > 0)
                sys.bilateral = [&](double t, const Vector& q, const Vector& u, Vector& f, Vector& phi, Matrix& C,
                                    Vector& r) {
                    put(q, &u);
                    bilateral_at(t, scratch.data(), f, phi, C, r);
                };
            runtime::contact::EventDrivenOptions<double> options;
            options.detect_zeno = request.zeno_ratios > 0;
            options.zeno_ratios = std::max(1, request.zeno_ratios);
            options.sequential_impacts = sequential;
            // The scene's [events], located on the driver's dense output, recorded like the other
            // drivers' (a CSV row labelled with the name, the state in the summary); terminal ones stop.
            for (std::size_t i = 0; i < n_ev; ++i)
                options.events.push_back(
                    {static_cast<runtime::EventDirection>(lib.event_directions()[i]), lib.event_terminal()[i]});
            if (n_ev > 0) {
                options.event_functions = [&](double t, const State<double>& xs, State<double>& h) {
                    lib.events(t, xs.data(), h.data(), parameters);
                };
                options.on_scene_event = [&](const runtime::EventHit<double>& hit, const Vector& lambda,
                                             const std::vector<bool>& active) {
                    for (std::size_t a = 0; a < m; ++a) {
                        lambda_now[a] = lambda[Eigen::Index(a)];
                        active_now[a] = active[a];
                    }
                    const std::string& name = lib.event_names()[hit.index];
                    record(hit.t, hit.x, {}, &name);
                    result.events.push_back({name, hit.t, hit.direction, hit.terminal, hit.x});
                };
            }
            options.on_event = [&](const runtime::contact::ContactEvent<double>& e) {
                ContactEventReport r;
                r.kind = contact_kind_name(e.kind);
                r.name = lib.contact_names()[e.contact];
                r.t = e.t;
                r.rate_before = e.rate_before;
                r.rate_after = e.rate_after;
                r.impulse = e.impulse;
                r.energy_change = e.energy_change;
                r.carnot = e.carnot;
                r.lambda = e.lambda;
                r.ratio = e.ratio;
                r.extrapolation_error = e.extrapolation_error;
                add_event(std::move(r));
            };
            const auto observer = [&](double t, const State<double>& xs, const Vector& lambda,
                                      const std::vector<bool>& active) {
                for (std::size_t a = 0; a < m; ++a) {
                    lambda_now[a] = lambda[Eigen::Index(a)];
                    active_now[a] = active[a];
                }
                record(t, xs, pending);
                pending.clear();
            };
            runtime::Limits limits;
            if (request.max_steps) limits.max_steps = *request.max_steps;
            const runtime::Tolerances tol{request.rtol, request.atol};
            const bool compensated = result.compensated;
            runtime::contact::EventDrivenOutcome<double> outcome;
            runtime::visit_integrator<double>(request.integrator, [&](auto tag) {
                using Tag = decltype(tag);
                using Stepper = typename Tag::type;
                if constexpr (Tag::info.kind == runtime::IntegratorKind::adaptive &&
                              runtime::DenseOutputStepper<Stepper>) {
                    Stepper stepper;
                    stepper.set_compensated(compensated);
                    outcome = runtime::contact::integrate_event_driven(stepper, sys, x, 0.0, request.t_end, tol,
                                                                       observer, options, limits);
                }
                return 0;
            });
            result.t = outcome.t;
            if (outcome.stopped) result.stopped_by = lib.event_names()[outcome.stopped_by];
            result.steps = outcome.stats.accepted;
            result.rejected = outcome.stats.rejected;
            result.rhs_evals = outcome.stats.rhs_evals;
        } else {
            using runtime::LcpMatrix;
            using runtime::LcpVector;
            State<double> scratch(x.size(), 0.0);
            std::vector<double> buffer(m * std::size_t(n) + std::size_t(n * n));
            const auto put = [&](const LcpVector<double>& q, const LcpVector<double>* u) {
                for (int k = 0; k < n; ++k) {
                    scratch[std::size_t(k)] = q[k];
                    scratch[std::size_t(n + k)] = u ? (*u)[k] : 0.0;
                }
            };
            const auto mass = [&](double t, const LcpVector<double>& q) {
                put(q, nullptr);
                lib.mass_matrix(t, scratch.data(), buffer.data(), parameters);
                LcpMatrix<double> M(n, n);
                for (int i = 0; i < n; ++i)
                    for (int j = 0; j < n; ++j) M(i, j) = buffer[std::size_t(i * n + j)];
                return M;
            };
            const auto force = [&](double t, const LcpVector<double>& q, const LcpVector<double>& u) {
                put(q, &u);
                LcpVector<double> f(n);
                lib.forcing(t, scratch.data(), f.data(), parameters);
                return f;
            };
            const auto gaps = [&](double t, const LcpVector<double>& q, const LcpVector<double>& u) {
                put(q, &u);
                LcpVector<double> g = LcpVector<double>::Zero(Eigen::Index(m));
                lib.gaps(t, scratch.data(), g.data(), parameters);
                return g;
            };
            // W at (q, u = 0): ∂f/∂q of a gap, ∂φ/∂u of a kinematic row (φ linear in u).
            const auto jacobian = [&](double t, const LcpVector<double>& q) {
                put(q, nullptr);
                lib.contact_jacobian(t, scratch.data(), buffer.data(), parameters);
                LcpMatrix<double> W = LcpMatrix<double>::Zero(Eigen::Index(m), n);
                for (std::size_t a = 0; a < m; ++a)
                    for (int k = 0; k < n; ++k) W(Eigen::Index(a), k) = buffer[a * std::size_t(n) + std::size_t(k)];
                return W;
            };
            LcpVector<double> q(n), u(n), e = LcpVector<double>::Zero(Eigen::Index(m));
            for (int k = 0; k < n; ++k) {
                q[k] = x[std::size_t(k)];
                u[k] = x[std::size_t(n + k)];
            }
            for (std::size_t a = 0; a < m; ++a) e[Eigen::Index(a)] = restitution[a];
            // w = ∂f/∂t of moving gaps (zeros for fixed ones): ḟ = W u + w.
            const auto time_rates = [&](double t, const LcpVector<double>& q) {
                put(q, nullptr);
                LcpVector<double> w = LcpVector<double>::Zero(Eigen::Index(m));
                lib.contact_time_rates(t, scratch.data(), w.data(), parameters);
                return w;
            };
            runtime::MoreauJeanOptions<double> options;
            options.theta = request.theta;
            options.kinematic = lib.contact_kinematic();
            if (lib.moving_contacts()) options.time_rates = time_rates;
            // M̃⁻¹ B: M⁻¹ B with the bilateral rows' reaction taken out (M⁻¹ B without them).
            const auto constrained_solve = [&](double t, const LcpVector<double>& q, const LcpVector<double>& u,
                                               const LcpMatrix<double>& M, const LcpMatrix<double>& B) {
                const Eigen::LDLT<LcpMatrix<double>> ldlt(M);
                LcpMatrix<double> out = ldlt.solve(B);
                if (k == 0) return out;
                Vector f, phi, r;
                Matrix C;
                put(q, &u);
                bilateral_at(t, scratch.data(), f, phi, C, r);
                const LcpMatrix<double> Y = ldlt.solve(LcpMatrix<double>(C.transpose()));
                out -= Y * (C * Y).ldlt().solve(LcpMatrix<double>(C * out));
                return out;
            };
            if (k > 0) {
                // C u_{k+1} = C u_k − φ(q_k, u_k): φ = 0 at the step's end, φ linear in u.
                options.bilateral = [&](double t, const LcpVector<double>& q, const LcpVector<double>& u,
                                        LcpMatrix<double>& C, LcpVector<double>& d) {
                    Vector f, phi, r;
                    put(q, &u);
                    bilateral_at(t, scratch.data(), f, phi, C, r);
                    d = C * u - phi;
                };
                options.project = [&](double t, LcpVector<double>& q, LcpVector<double>& u) {
                    put(q, &u);
                    project_bilateral(t, scratch.data());
                    for (int j = 0; j < n; ++j) {
                        q[j] = scratch[std::size_t(j)];
                        u[j] = scratch[std::size_t(n + j)];
                    }
                };
                project_bilateral(0.0, x.data());
                for (int j = 0; j < n; ++j) {
                    q[j] = x[std::size_t(j)];
                    u[j] = x[std::size_t(n + j)];
                }
            }
            record(0.0, x, {});
            // The step's events from its impulses: P_α > 0 with an approaching rate that leaves
            // separating is an impact (ΔT over the step, Carnot's loss of the impulsive Δu = M⁻¹W_αᵀP_α);
            // P_α > 0 leaving the row at rest is the active set (λ ≈ P/h); a contact ends when P_α is 0.
            LcpVector<double> q_prev = q, u_prev = u;
            double t_prev = 0.0;
            const double h = request.step;
            const auto observer = [&](double t, const LcpVector<double>& qn, const LcpVector<double>& un,
                                      const runtime::MoreauJeanStep<double>& step) {
                const double dt = t - t_prev;
                const double scale = 1e-9 * (1.0 + un.cwiseAbs().maxCoeff() + u_prev.cwiseAbs().maxCoeff());
                bool any = false;
                for (std::size_t a = 0; a < m; ++a) any = any || step.P[Eigen::Index(a)] > 0.0;
                LcpMatrix<double> W, M;
                LcpVector<double> kick;  // the velocity the forces add over one step, h M⁻¹ f
                LcpVector<double> w0 = LcpVector<double>::Zero(Eigen::Index(m)), w1 = w0;  // ∂f/∂t at t_prev, t
                if (any && lib.moving_contacts()) {
                    w0 = time_rates(t_prev, q_prev);
                    w1 = time_rates(t, q_prev);
                }
                if (any) {
                    W = jacobian(t_prev, q_prev);
                    M = mass(t_prev, q_prev);
                    kick = dt * constrained_solve(t_prev, q_prev, u_prev, M,
                                                  LcpMatrix<double>(force(t_prev, q_prev, u_prev)));
                }
                for (std::size_t a = 0; a < m; ++a) {
                    const double P = step.P[Eigen::Index(a)];
                    bool now = false;
                    if (P > 0.0 && lib.contact_kinematic()[a]) {
                        now = true;  // a kinematic row takes no impact: P is its reaction over the step
                    } else if (P > 0.0) {
                        // A bounce slower than twice what the forces change in one step is the scheme's
                        // own chatter at rest (order h), not an impact: the row counts as in contact.
                        const Eigen::Index ia = Eigen::Index(a);
                        const double before = W.row(ia).dot(u_prev) + w0[ia], after = W.row(ia).dot(un) + w1[ia];
                        const double vtol = scale + 2 * std::abs(W.row(Eigen::Index(a)).dot(kick));
                        if (before < -vtol && after > vtol) {
                            ContactEventReport r;
                            r.kind = "impact";
                            r.name = lib.contact_names()[a];
                            r.t = t;
                            r.rate_before = before;
                            r.rate_after = after;
                            r.impulse = P;
                            r.energy_change = 0.5 * un.dot(M * un) - 0.5 * u_prev.dot(M * u_prev);
                            const LcpVector<double> du = constrained_solve(
                                t_prev, q_prev, u_prev, M, LcpMatrix<double>(W.row(Eigen::Index(a)).transpose() * P));
                            // Carnot's loss in the wall's frame, less the moving wall's work P w.
                            r.carnot = -((1.0 - restitution[a]) / (1.0 + restitution[a])) * 0.5 * du.dot(M * du) -
                                       P * w0[ia];
                            add_event(std::move(r));
                        } else {
                            now = true;
                        }
                    }
                    if (now && !active_now[a]) {
                        ContactEventReport r;
                        r.kind = "contact";
                        r.name = lib.contact_names()[a];
                        r.t = t;
                        r.lambda = P / dt;
                        add_event(std::move(r));
                    } else if (!now && active_now[a]) {
                        ContactEventReport r;
                        r.kind = "separation";
                        r.name = lib.contact_names()[a];
                        r.t = t;
                        add_event(std::move(r));
                    }
                    active_now[a] = now;
                    lambda_now[a] = P / dt;
                }
                State<double> xs(x.size());
                for (int k = 0; k < n; ++k) {
                    xs[std::size_t(k)] = qn[k];
                    xs[std::size_t(n + k)] = un[k];
                }
                record(t, xs, pending);
                pending.clear();
                q_prev = qn;
                u_prev = un;
                t_prev = t;
            };
            const long steps = runtime::integrate_moreau_jean<double>(mass, force, gaps, jacobian, e, 0.0, request.t_end,
                                                                     h, q, u, observer, options);
            for (int k = 0; k < n; ++k) {
                x[std::size_t(k)] = q[k];
                x[std::size_t(n + k)] = u[k];
            }
            result.t = request.t_end;
            result.steps = std::size_t(steps);
            result.rhs_evals = 2 * std::size_t(steps);
        }
    } catch (const CsvOutput::RowLimit& limit) {
        throw std::runtime_error(fmt::format("simulating {} with {}: the CSV {} reached its limit of {} rows at t = {} "
                                             "(of t_end = {}) and was not written; raise --max-rows, shorten --t-end, "
                                             "or run without --output",
                                             scene, request.contact_method, request.csv_path, request.max_rows,
                                             number(limit.t), number(request.t_end)));
    } catch (const runtime::IntegrationError& e) {
        throw failed_run(e, request, scene, state_names, t_last, x_last, csv);
    }
    result.wall_s = seconds_since(start);
    csv.commit();
    for (std::size_t i = 0; i < x.size(); ++i) result.state.emplace_back(state_names[i], x[i]);
    if (!outputs.empty()) {
        lib.outputs(result.t, x.data(), outputs.data(), parameters);
        for (std::size_t i = 0; i < outputs.size(); ++i) result.outputs.emplace_back(lib.output_names()[i], outputs[i]);
    }
    for (std::size_t i = 0; i < n_inv; ++i)
        result.invariants.push_back({lib.invariant_names()[i], inv0[i], inv[i], max_drift[i]});
    for (std::size_t a = 0; a < m; ++a) {
        result.contacts[a].lambda = lambda_now[a];
        result.contacts[a].active = active_now[a];
    }
    if (!request.csv_path.empty()) {
        result.csv_path = request.csv_path;
        result.csv_rows = csv.rows();
    }
    return result;
}

}  // namespace

SimulationResult simulate(const SimulationRequest& request) {
    validate(request);  // before the compile: a typo costs none
    const KernelLibrary lib = KernelLibrary::load(request.header_text, request.struct_name, request.cache_dir);
    return simulate_loaded(request, lib);
}

void validate_request(const SimulationRequest& request) { validate(request); }

void resolve_start(const SimulationRequest& request, const KernelLibrary& lib, std::vector<double>& parameters,
                   std::vector<double>& x) {
    parameters = lib.parameter_defaults();
    x.assign(lib.initial_state().begin(), lib.initial_state().end());
    apply_overrides(request, lib, parameters, x);
}

SimulationResult simulate_loaded(const SimulationRequest& request, const KernelLibrary& lib) {
    validate(request);
    std::vector<double> parameter_values = lib.parameter_defaults();
    State<double> x(lib.initial_state().begin(), lib.initial_state().end());
    apply_overrides(request, lib, parameter_values, x);
    const KernelLibrary::Parameters parameters = lib.make_parameters(parameter_values);
    refuse_start_below_surface(request, lib, parameters, x);

    SimulationResult result;
    result.scene_name = lib.scene_name();
    const bool compensated = request.compensated.value_or(scene::compensated_by_default(request.integrator));
    result.integrator = describe_method(request, compensated);
    if (const runtime::IntegratorInfo* info = runtime::find_integrator(request.integrator); info && info->uses_jacobian)
        result.integrator.insert(result.integrator.size() - 1, ", " + jacobian_source(request, lib));  // inside the parentheses
    result.compensated = compensated;
    result.compile_s = lib.seconds();
    result.cache_hit = lib.cache_hit();
    result.library_path = lib.library_path();
    for (std::size_t i = 0; i < parameter_values.size(); ++i)
        result.parameters.emplace_back(lib.parameter_names()[i], parameter_values[i]);

    if (!lib.contact_names().empty()) return simulate_contacts(request, lib, parameters, x, std::move(result));
    check_separable(request.integrator, request.integrator_pos, lib.separable(), lib.scene_name());
    std::vector<std::string> state_names = lib.state_names();
    if (request.variational) extend_by_transition_matrix(request, lib, x, state_names);

    const std::size_t n_inv = lib.invariant_names().size(), n_ev = lib.event_names().size();
    std::vector<std::string> columns{"t"};
    columns.insert(columns.end(), state_names.begin(), state_names.end());
    columns.insert(columns.end(), lib.invariant_names().begin(), lib.invariant_names().end());
    columns.insert(columns.end(), lib.output_names().begin(), lib.output_names().end());
    if (n_ev > 0) columns.push_back("event");  // only for scenes with [events]: other CSVs keep their shape
    CsvOutput csv(request.csv_path, columns, request.max_rows);
    std::vector<double> outputs(lib.output_names().size());

    std::vector<runtime::EventSpec> specs;
    for (std::size_t i = 0; i < n_ev; ++i)
        specs.push_back({static_cast<runtime::EventDirection>(lib.event_directions()[i]), lib.event_terminal()[i]});
    runtime::EventLocator<double> locator(specs);

    // One CSV row (and one look at the invariants) at t0, after every step and at every event.
    std::vector<double> inv(n_inv), inv0(n_inv), max_drift(n_inv, 0.0);
    const std::size_t n_con = lib.constraint_names().size();
    std::vector<double> residual(n_con), max_residual(n_con, 0.0);
    State<double> projected;
    bool first = true;
    double t_last = 0.0;
    State<double> x_last = x;
    ProgressBar progress(request.progress, request.t_end);
    SingularSetWatch singular(lib, parameters);
    ProgramWatch programs(lib, parameters);
    auto record = [&](double t, const State<double>& xs, const std::string* event) {
        singular.check(t, xs);  // before the row: no state past the set is written
        programs.observe(t, xs);
        lib.invariants(t, xs.data(), inv.data(), parameters);
        if (first) inv0 = inv, first = false;
        for (std::size_t i = 0; i < n_inv; ++i) max_drift[i] = track_max(max_drift[i], std::abs(inv[i] - inv0[i]));
        if (n_con > 0) {
            // The drivers project after the observer has seen the step: the residuals are those of
            // the state the integration carries on from (project() of the same x at the same t).
            if (lib.projects()) {
                projected = xs;
                lib.project(t, projected.data(), parameters);
            }
            lib.constraint_residuals(t, (lib.projects() ? projected : xs).data(), residual.data(), parameters);
            for (std::size_t i = 0; i < n_con; ++i) max_residual[i] = track_max(max_residual[i], std::abs(residual[i]));
        }
        if (!outputs.empty() && !request.csv_path.empty()) lib.outputs(t, xs.data(), outputs.data(), parameters);
        csv.row(t, xs, inv, outputs, n_ev > 0 ? event : nullptr, n_ev > 0);
        t_last = t;
        x_last = xs;
        progress.update(t);
    };
    StiffnessWatch stiffness(request, lib, parameters);
    auto observer = [&](double t, const State<double>& xs) {
        if (!first) stiffness.step(t_last, t, xs);
        record(t, xs, nullptr);
    };
    auto on_event = [&](const runtime::EventHit<double>& hit) {
        const std::string& name = lib.event_names()[hit.index];
        record(hit.t, hit.x, &name);
        result.events.push_back({name, hit.t, hit.direction, hit.terminal, hit.x});
    };

    const auto start = Clock::now();
    runtime::EventOutcome<double> outcome;
    try {
        outcome = integrate(request, compensated, KernelSystem{lib, parameters, request.variational}, x, locator,
                            observer, on_event);
    } catch (const CsvOutput::RowLimit& limit) {
        // Not a failure of the integration but a refusal of its size: nothing is kept.
        throw std::runtime_error(fmt::format("simulating {} with {}: the CSV {} reached its limit of {} rows at t = {} "
                                             "(of t_end = {}) and was not written; raise --max-rows, shorten --t-end, "
                                             "or run without --output",
                                             lib.scene_name(), request.integrator, request.csv_path, request.max_rows,
                                             number(limit.t), number(request.t_end)));
    } catch (const runtime::IntegrationError& e) {
        if (e.kind() != runtime::IntegrationError::Kind::singular_set && !first) try {
                singular.fail_if_near_control_set(t_last, x_last);
            } catch (const runtime::IntegrationError& control) {
                throw failed_run(control, request, lib.scene_name(), state_names, t_last, x_last, csv);
            }
        if (e.kind() == runtime::IntegrationError::Kind::non_finite && !first) {
            const std::string near = singular.near(t_last, x_last);
            if (!near.empty())
                throw failed_run(runtime::IntegrationError(e.kind(), e.t(), e.what() + near, e.component()), request,
                                 lib.scene_name(), state_names, t_last, x_last, csv);
        }
        throw failed_run(e, request, lib.scene_name(), state_names, t_last, x_last, csv);
    }
    result.wall_s = seconds_since(start);
    csv.commit();

    result.t = outcome.t;
    if (outcome.stopped) result.stopped_by = lib.event_names()[outcome.event];
    for (std::size_t i = 0; i < x.size(); ++i) result.state.emplace_back(state_names[i], x[i]);
    if (!outputs.empty()) {
        lib.outputs(result.t, x.data(), outputs.data(), parameters);
        for (std::size_t i = 0; i < outputs.size(); ++i) result.outputs.emplace_back(lib.output_names()[i], outputs[i]);
    }
    for (std::size_t i = 0; i < n_inv; ++i)
        result.invariants.push_back({lib.invariant_names()[i], inv0[i], inv[i], max_drift[i]});
    for (std::size_t i = 0; i < n_con; ++i) result.constraints.push_back({lib.constraint_names()[i], max_residual[i]});
    result.programs = programs.reports();
    result.steps = outcome.stats.accepted;
    result.rejected = outcome.stats.rejected;
    result.rhs_evals = outcome.stats.rhs_evals;
    result.hint = stiffness.hint(request.integrator);
    if (!request.csv_path.empty()) {
        result.csv_path = request.csv_path;
        result.csv_rows = csv.rows();
    }
    return result;
}

void print_summary(const SimulationResult& r, const std::string& format, std::ostream& out) {
    if (format == "json") {
        std::string s = fmt::format("{{\"t\": {}, \"state\": {{", json_number(r.t));
        for (std::size_t i = 0; i < r.state.size(); ++i)
            s += fmt::format("{}{}: {}", i ? ", " : "", json_string(r.state[i].first), json_number(r.state[i].second));
        s += "}, \"outputs\": {";
        for (std::size_t i = 0; i < r.outputs.size(); ++i)
            s += fmt::format("{}{}: {}", i ? ", " : "", json_string(r.outputs[i].first), json_number(r.outputs[i].second));
        s += "}, \"invariants\": {";
        for (std::size_t i = 0; i < r.invariants.size(); ++i) {
            const auto& v = r.invariants[i];
            s += fmt::format("{}{}: {{\"initial\": {}, \"max_abs_drift\": {}}}", i ? ", " : "", json_string(v.name),
                             json_number(v.initial), json_number(v.max_abs_drift));
        }
        s += "}, \"events\": [";
        for (std::size_t i = 0; i < r.events.size(); ++i) {
            const auto& e = r.events[i];
            s += fmt::format("{}{{\"name\": {}, \"t\": {}, \"direction\": \"{}\", \"terminal\": {}, \"state\": {{",
                             i ? ", " : "", json_string(e.name), json_number(e.t), e.direction > 0 ? "up" : "down",
                             e.terminal ? "true" : "false");
            for (std::size_t k = 0; k < e.state.size() && k < r.state.size(); ++k)
                s += fmt::format("{}{}: {}", k ? ", " : "", json_string(r.state[k].first), json_number(e.state[k]));
            s += "}}";
        }
        s += "]";
        if (!r.constraints.empty()) {  // only kernels with constraint rows: other summaries keep their shape
            s += ", \"constraints\": {";
            for (std::size_t i = 0; i < r.constraints.size(); ++i)
                s += fmt::format("{}{}: {{\"max_abs_residual\": {}}}", i ? ", " : "", json_string(r.constraints[i].name),
                                 json_number(r.constraints[i].max_abs_residual));
            s += "}";
        }
        if (!r.programs.empty()) {  // only kernels with programs
            s += ", \"programs\": {";
            for (std::size_t i = 0; i < r.programs.size(); ++i) {
                const auto& g = r.programs[i];
                s += fmt::format("{}{}: {{\"law\": {}, \"initial\": {}, \"initial_rate\": {}, \"final\": {}, "
                                 "\"max_abs_residual\": {}, \"max_departure\": {}}}",
                                 i ? ", " : "", json_string(g.name), json_string(g.law), json_number(g.initial),
                                 json_number(g.initial_rate), json_number(g.final), json_number(g.max_abs_residual),
                                 json_number(g.max_departure));
            }
            s += "}";
        }
        if (!r.contacts.empty()) {  // only kernels with unilateral rows
            s += fmt::format(", \"contacts\": {{\"method\": {}, \"impact_law\": {}, \"rows\": {{",
                             json_string(r.contact_method), json_string(r.impact_law));
            for (std::size_t i = 0; i < r.contacts.size(); ++i) {
                const auto& c = r.contacts[i];
                s += fmt::format("{}{}: {{\"kinematic\": {}, \"restitution\": {}, \"lambda\": {}, \"active\": {}, "
                                 "\"impacts\": {}}}",
                                 i ? ", " : "", json_string(c.name), c.kinematic ? "true" : "false",
                                 json_number(c.restitution), json_number(c.lambda), c.active ? "true" : "false", c.impacts);
            }
            s += "}, \"impacts\": [";
            bool any = false;
            for (const auto& e : r.contact_events) {
                if (e.kind != "impact") continue;
                s += fmt::format("{}{{\"row\": {}, \"t\": {}, \"rate_before\": {}, \"rate_after\": {}, \"impulse\": {}, "
                                 "\"energy_change\": {}, \"carnot\": {}}}",
                                 any ? ", " : "", json_string(e.name), json_number(e.t), json_number(e.rate_before),
                                 json_number(e.rate_after), json_number(e.impulse), json_number(e.energy_change),
                                 json_number(e.carnot));
                any = true;
            }
            s += "], \"zeno\": [";
            any = false;
            for (const auto& e : r.contact_events) {
                if (e.kind != "zeno") continue;
                s += fmt::format("{}{{\"row\": {}, \"t\": {}, \"ratio\": {}, \"extrapolation_error\": {}}}",
                                 any ? ", " : "", json_string(e.name), json_number(e.t), json_number(e.ratio),
                                 json_number(e.extrapolation_error));
                any = true;
            }
            s += "], \"events\": [";
            for (std::size_t i = 0; i < r.contact_events.size(); ++i) {
                const auto& e = r.contact_events[i];
                s += fmt::format("{}{{\"kind\": {}, \"row\": {}, \"t\": {}{}}}", i ? ", " : "", json_string(e.kind),
                                 json_string(e.name), json_number(e.t),
                                 e.kind == "contact" ? fmt::format(", \"lambda\": {}", json_number(e.lambda)) : "");
            }
            s += "]}";
        }
        if (!r.hint.empty()) s += fmt::format(", \"hint\": {}", json_string(r.hint));  // only stability-limited runs
        s += fmt::format(", \"stopped_by\": {}, \"compensated\": {}",
                         r.stopped_by.empty() ? "null" : json_string(r.stopped_by), r.compensated ? "true" : "false");
        s += fmt::format(", \"steps\": {}, \"rejected\": {}, \"rhs_evals\": {}, \"wall_s\": {}, \"compile_s\": {}, "
                         "\"cache_hit\": {}}}\n",
                         r.steps, r.rejected, r.rhs_evals, json_number(r.wall_s), json_number(r.compile_s),
                         r.cache_hit ? "true" : "false");
        out << s;
        return;
    }
    if (format != "text")
        throw InputError(SourcePos{"--summary"}, fmt::format("unknown summary format '{}' (expected text or json)", format));

    std::size_t width = 6;  // aligns the values of the longest name
    for (const auto& [n, v] : r.state) width = std::max(width, n.size());
    for (const auto& [n, v] : r.outputs) width = std::max(width, n.size());
    for (const auto& v : r.invariants) width = std::max(width, v.name.size());
    for (const auto& e : r.events) width = std::max(width, e.name.size());
    for (const auto& c : r.constraints) width = std::max(width, c.name.size());
    for (const auto& c : r.contacts) width = std::max(width, c.name.size());

    std::string s = fmt::format("{}: {} to t = {}{}\n", r.scene_name, r.integrator, number(r.t),
                                r.stopped_by.empty() ? "" : fmt::format(", stopped by the terminal event '{}'", r.stopped_by));
    if (!r.hint.empty()) s += fmt::format("hint: {}\n", r.hint);
    s += "final state\n";
    for (const auto& [n, v] : r.state) s += fmt::format("  {:<{}}  {:>24}\n", n, width, number(v));
    if (!r.outputs.empty()) s += "outputs\n";
    for (const auto& [n, v] : r.outputs) s += fmt::format("  {:<{}}  {:>24}\n", n, width, number(v));
    if (!r.invariants.empty()) {
        s += fmt::format("invariants\n  {:<{}}  {:>24}  {:>12}  {:>12}\n", "", width, "initial", "max |drift|", "relative");
        for (const auto& v : r.invariants) {
            const double rel = v.relative_drift();
            s += fmt::format("  {:<{}}  {:>24}  {:>12.3g}  {:>12}\n", v.name, width, number(v.initial), v.max_abs_drift,
                             std::isnan(rel) && !std::isnan(v.max_abs_drift) ? "-" : fmt::format("{:.3g}", rel));
        }
    }
    if (!r.events.empty()) {
        // Each event once per crossing; a long run lists the first ones (all are in the CSV and the JSON).
        constexpr std::size_t shown = 20;
        s += fmt::format("events      {} located\n", r.events.size());
        for (std::size_t i = 0; i < r.events.size() && i < shown; ++i) {
            const auto& e = r.events[i];
            s += fmt::format("  {:<{}}  t = {:>24}  {}{}\n", e.name, width, number(e.t), e.direction > 0 ? "up" : "down",
                             e.terminal ? ", terminal" : "");
        }
        if (r.events.size() > shown) s += fmt::format("  ... {} more\n", r.events.size() - shown);
    }
    if (!r.constraints.empty()) {
        s += fmt::format("constraints\n  {:<{}}  {:>24}\n", "", width, "max |residual|");
        for (const auto& c : r.constraints) s += fmt::format("  {:<{}}  {:>24.3g}\n", c.name, width, c.max_abs_residual);
    }
    if (!r.programs.empty()) {
        s += fmt::format("programs\n  {:<{}}  {:>12}  {:>12}  {:>14}  {}\n", "", width, "initial", "final",
                         "max departure", "law");
        for (const auto& g : r.programs)
            s += fmt::format("  {:<{}}  {:>12.4g}  {:>12.4g}  {:>14.3g}  {}\n", g.name, width, g.initial, g.final,
                             g.max_departure, g.law);
    }
    if (!r.contacts.empty()) {
        s += fmt::format("contacts    {}, {} impacts\n  {:<{}}  {:>5}  {:>24}  {:>6}  {:>7}\n", r.contact_method,
                         r.impact_law, "", width, "e", "lambda", "active", "impacts");
        for (const auto& c : r.contacts)
            s += fmt::format("  {:<{}}  {:>5}  {:>24}  {:>6}  {:>7}{}\n", c.name, width, number(c.restitution),
                             number(c.lambda), c.active ? "yes" : "no", c.impacts, c.kinematic ? "  (kinematic)" : "");
        std::size_t impacts = 0;
        for (const auto& e : r.contact_events) impacts += e.kind == "impact";
        if (impacts > 0) {
            // Every impact (the JSON and the CSV have them too): the rates f-dot before and after, the
            // percussion P, the kinetic energy change and Carnot's prediction of it.
            s += fmt::format("impacts     {}\n  {:<{}}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}\n", impacts, "",
                             width, "t", "rate before", "rate after", "P", "delta T", "Carnot");
            for (const auto& e : r.contact_events)
                if (e.kind == "impact")
                    s += fmt::format("  {:<{}}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}\n", e.name, width,
                                     number(e.t), number(e.rate_before), number(e.rate_after), number(e.impulse),
                                     number(e.energy_change), number(e.carnot));
        }
        for (const auto& e : r.contact_events)
            if (e.kind == "zeno")
                s += fmt::format("zeno        {} at t = {} (interval ratio {}, extrapolation error {:.3g})\n", e.name,
                                 number(e.t), number(e.ratio), e.extrapolation_error);
        std::size_t listed = 0, phases = 0;  // the first 20 contact phases and separations (all in the JSON)
        for (const auto& e : r.contact_events)
            if (e.kind == "contact" || e.kind == "separation") {
                if (++phases > 20) continue;
                ++listed;
                s += fmt::format("{:<12}{} at t = {}{}\n", e.kind, e.name, number(e.t),
                                 e.kind == "contact" ? fmt::format(" (lambda {})", number(e.lambda)) : "");
            }
        if (phases > listed) s += fmt::format("            ... {} more contact and separation events\n", phases - listed);
    }
    s += fmt::format("steps       {} accepted, {} rejected, {} rhs evaluations\n", r.steps, r.rejected, r.rhs_evals);
    s += fmt::format("time        integration {:.3g} s; kernel {:.3g} s ({})\n", r.wall_s, r.compile_s,
                     r.cache_hit ? "cached: " + r.library_path : "compiled into " + r.library_path);
    if (!r.csv_path.empty()) s += fmt::format("csv         {} ({} rows)\n", r.csv_path, r.csv_rows);
    out << s;
}

}  // namespace eomc::host
