// A kernel without unilateral rows, integrated by the request's method through the runtime's
// registry, with the kernel's events, watches and CSV.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "eomc/runtime/runtime.hpp"
#include "host/simulate/runs.hpp"

namespace eomc::host {

namespace {

using runtime::State;

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

// The variational run extends the state by Φ, starting from the identity, and names its entries.
void extend_by_transition_matrix(const Run& run, State<double>& x, std::vector<std::string>& state_names) {
    if (!run.lib.variational()) throw std::runtime_error("the kernel has no variational_rhs: generate it with --variational");
    const runtime::IntegratorInfo& method = *run.settings.method;
    if (method.needs_separable)
        throw InputError(run.request.integrator_pos,
                         fmt::format("the {} integrator steps q and q̇ by the acceleration alone and cannot carry "
                                     "the variational equations; use {}",
                                     method.name,
                                     runtime::integrator_list([](const auto& i) { return !i.needs_separable; }, ", ", " or ")));
    const std::size_t n = x.size();
    x.resize(n + n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        x[n + i * n + i] = 1.0;
        for (std::size_t j = 0; j < n; ++j) state_names.push_back(fmt::format("Phi_{}_{}", i, j));
    }
}

// The request's method over [0, t_end] from x (advanced in place), with the kernel's events: the
// one ladder from a method's traits to its driver and options.
template <class Observer, class OnEvent>
runtime::EventOutcome<double> integrate(const Run& run, State<double>& x, runtime::EventLocator<double>& locator,
                                        Observer&& observer, OnEvent&& on_event) {
    const KernelLibrary& lib = run.lib;
    const RunSettings& s = run.settings;
    const double t_end = run.request.t_end;
    KernelSystem sys{lib, run.parameters, run.request.variational};
    auto acceleration = [&](double t, const State<double>& q, State<double>& a) {
        lib.acceleration(t, q.data(), a.data(), run.parameters);
    };
    auto event_functions = [&](double t, const State<double>& xs, State<double>& g) {
        lib.events(t, xs.data(), g.data(), run.parameters);
    };
    auto fixed_step = [&](auto&& stepper, auto& f) {
        // The step count is the user's choice here, not a sign of no progress: the budget must
        // not stop a long fixed-step run short of t_end. resolve_settings() bounded it by max_steps;
        // the two spare attempts are the runtime's (a last partial step, an event re-step).
        runtime::Limits limits;
        const double steps = std::ceil(t_end / s.step) + 2.0;
        limits.max_steps = std::max(limits.max_steps, static_cast<std::size_t>(steps));
        return runtime::integrate_fixed_events(stepper, f, x, 0.0, t_end, s.step, locator, event_functions, observer,
                                               on_event, limits);
    };
    auto adaptive = [&](auto&& stepper, auto& system) {
        stepper.set_compensated(s.compensated);
        runtime::Limits limits;
        if (run.request.max_steps) limits.max_steps = *run.request.max_steps;
        return runtime::integrate_adaptive_events(stepper, system, x, 0.0, t_end, 0.0, s.tolerances, locator,
                                                  event_functions, observer, on_event, limits);
    };
    runtime::GaussLegendreOptions gauss;
    gauss.compensated = s.compensated;
    runtime::SplittingOptions splitting;
    splitting.compensated = s.compensated;
    return runtime::visit_integrator<double>(s.method->name, [&](auto tag) {
        using Tag = decltype(tag);
        using Stepper = typename Tag::type;
        if constexpr (Tag::info.uses_jacobian) {
            if (!symbolic_jacobian(run)) return adaptive(Stepper{}, sys);
            KernelJacobianSystem jsys{sys, {}};
            return adaptive(Stepper{}, jsys);
        } else if constexpr (!Tag::info.fixed_step()) {
            return adaptive(Stepper{}, sys);
        } else if constexpr (Tag::info.needs_separable) {
            return fixed_step(Stepper{splitting}, acceleration);
        } else if constexpr (Tag::info.kind == runtime::IntegratorKind::implicit) {
            return fixed_step(Stepper{gauss}, sys);
        } else {
            Stepper stepper;
            stepper.set_compensated(s.compensated);
            return fixed_step(stepper, sys);
        }
    });
}

// The failure of a smooth run, told by what the watches know: a program's control matrix gone
// singular, or a non-finite value next to a singular set of the mass matrix.
runtime::IntegrationError explain_failure(const runtime::IntegrationError& e, Recorder& recorder,
                                          SingularSetWatch& singular, std::string_view method) {
    if (e.kind() != runtime::IntegrationError::Kind::singular_set && recorder.started()) try {
            singular.fail_if_near_control_set(recorder.t_last(), recorder.x_last());
        } catch (const runtime::IntegrationError& control) {
            return recorder.failed(control, method);
        }
    if (e.kind() == runtime::IntegrationError::Kind::non_finite && recorder.started()) {
        const std::string near = singular.near(recorder.t_last(), recorder.x_last());
        if (!near.empty())
            return recorder.failed(runtime::IntegrationError(e.kind(), e.t(), e.what() + near, e.component()), method);
    }
    return recorder.failed(e, method);
}

}  // namespace

bool symbolic_jacobian(const Run& run) {
    return run.lib.has_jacobian() && !run.request.variational && run.lib.contact_names().empty();
}

std::string jacobian_source(const Run& run) {
    if (symbolic_jacobian(run)) return "the kernel's symbolic Jacobian";
    if (run.request.variational) return "finite-difference Jacobian: the variational state has none";
    if (!run.lib.contact_names().empty()) return "finite-difference Jacobian: the contact phases' rates have none";
    return "finite-difference Jacobian: the kernel was generated without one";
}

SimulationResult simulate_smooth(const Run& run, State<double>& x, SimulationResult result) {
    const KernelLibrary& lib = run.lib;
    const RunSettings& s = run.settings;
    check_separable(*s.method, run.request.integrator_pos, lib.separable(), lib.scene_name());
    std::vector<std::string> state_names = lib.state_names();
    if (run.request.variational) extend_by_transition_matrix(run, x, state_names);

    const std::size_t n_ev = lib.event_names().size();
    std::vector<runtime::EventSpec> specs;
    for (std::size_t i = 0; i < n_ev; ++i)
        specs.push_back({static_cast<runtime::EventDirection>(lib.event_directions()[i]), lib.event_terminal()[i]});
    runtime::EventLocator<double> locator(specs);

    // One CSV row (and one look at the watches) at t0, after every step and at every event; the
    // event column only for scenes with [events]: other CSVs keep their shape.
    Recorder recorder(run, state_names, {}, n_ev > 0, x);
    SingularSetWatch singular(lib, run.parameters);
    ProgramWatch programs(lib, run.parameters);
    ConstraintWatch constraints(lib, run.parameters);
    StiffnessWatch stiffness(*s.method, run.request.variational, lib, run.parameters);
    const auto record = [&](double t, const State<double>& xs, const std::string* event) {
        singular.check(t, xs);  // before the row: no state past the set is written
        programs.observe(t, xs);
        constraints.observe(t, xs);
        recorder.record(t, xs, event);
    };
    auto observer = [&](double t, const State<double>& xs) {
        if (recorder.started()) stiffness.step(recorder.t_last(), t, xs);
        record(t, xs, nullptr);
    };
    auto on_event = [&](const runtime::EventHit<double>& hit) {
        const std::string& name = lib.event_names()[hit.index];
        record(hit.t, hit.x, &name);
        result.events.push_back({name, hit.t, hit.direction, hit.terminal, hit.x});
    };

    const auto start = std::chrono::steady_clock::now();
    runtime::EventOutcome<double> outcome;
    try {
        outcome = integrate(run, x, locator, observer, on_event);
    } catch (const CsvOutput::RowLimit& limit) {
        throw recorder.row_limit(limit, s.method->name);
    } catch (const runtime::IntegrationError& e) {
        throw explain_failure(e, recorder, singular, s.method->name);
    }
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    recorder.finish(outcome.t, x, result);
    if (outcome.stopped) result.stopped_by = lib.event_names()[outcome.event];
    result.constraints = constraints.reports();
    result.programs = programs.reports();
    result.steps = outcome.stats.accepted;
    result.rejected = outcome.stats.rejected;
    result.rhs_evals = outcome.stats.rhs_evals;
    result.hint = stiffness.hint();
    if (std::string w = unresolved_events_warning(locator.unresolved(), locator.first_unresolved()); !w.empty())
        result.warnings.push_back(std::move(w));
    if (n_ev > 0 && s.method->fixed_step())
        result.warnings.push_back(fmt::format("the events are compared at the ends of each fixed step of {}: a crossing "
                                              "and its return within one step are not seen (an adaptive method "
                                              "resolves them)",
                                              number(s.step)));
    return result;
}

}  // namespace eomc::host
