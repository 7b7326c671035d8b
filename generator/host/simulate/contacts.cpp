// Kernels with unilateral rows (Mei, Special Topics in Analytical Mechanics, ch. 6): the kernel's
// blocks as one runtime::contact::ContactSystem (runtime/contact/from_kernel.hpp), integrated by
// the event-driven hybrid driver (runtime/contact/event_driven.hpp) or by Moreau–Jean time stepping
// (runtime/contact/moreau_jean.hpp; V. Acary, B. Brogliato, Numerical Methods for Nonsmooth
// Dynamical Systems, Springer 2008). Both report their events the same way. The CSV gains
// lambda_<row> per row and `active`, the active set as a bitmask (bit α, value 2^α, set when row α
// is in the active set: 0 in free flight, 1 for a single row in contact), and the event column
// labels the rows written at transitions impact:<row>, contact:<row>, separation:<row>, zeno:<row>
// (one row per event, the state after the transition).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "eomc/runtime/contact/event_driven.hpp"
#include "eomc/runtime/contact/from_kernel.hpp"
#include "eomc/runtime/contact/moreau_jean.hpp"
#include "eomc/runtime/registry.hpp"
#include "host/simulate/runs.hpp"

namespace eomc::host {

namespace {

using runtime::State;
using runtime::contact::ContactMethod;
using Vector = runtime::contact::Vector<double>;

// The loaded kernel's contact blocks (runtime::contact::ContactBlocks) at its parameters.
struct LibraryContactBlocks {
    const KernelLibrary& lib;
    const KernelLibrary::Parameters& p;

    int dof() const { return lib.n_coordinates(); }
    std::size_t contact_count() const { return lib.contact_names().size(); }
    bool kinematic(std::size_t a) const { return lib.contact_kinematic()[a]; }
    void restitutions(double* e) const { lib.restitutions(p, e); }
    void mass_matrix(double t, const double* x, double* out) const { lib.mass_matrix(t, x, out, p); }
    void forcing(double t, const double* x, double* out) const { lib.forcing(t, x, out, p); }
    void gaps(double t, const double* x, double* out) const { lib.gaps(t, x, out, p); }
    void contact_jacobian(double t, const double* x, double* out) const { lib.contact_jacobian(t, x, out, p); }
    void contact_bias(double t, const double* x, double* out) const { lib.contact_bias(t, x, out, p); }
    bool moving() const { return lib.moving_contacts(); }
    void contact_time_rates(double t, const double* x, double* out) const { lib.contact_time_rates(t, x, out, p); }
    std::size_t bilateral_count() const { return lib.constraint_names().size(); }
    bool bilateral_holonomic(std::size_t i) const { return lib.constraint_holonomic()[i]; }
    void constraint_rows(double t, const double* x, double* f, double* phi, double* C, double* r) const {
        lib.constraint_rows(t, x, f, phi, C, r, p);
    }
};

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

// The drivers assume q̇ = u (W = ∂f/∂q acts on the velocities, the impact law on q̇): the kernel's
// velocity block must follow its coordinates, as many, and its coordinate rates must be those
// velocities. The last is probed at the start state and at a shifted one with distinct velocities:
// a kernel with q̇ = u writes the rate as a copy of the velocity (exact), one with quasi-velocities
// (q̇ = A(q) u) does not.
void require_rates_are_velocities(const Run& run, const State<double>& x0) {
    const KernelLibrary& lib = run.lib;
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
        lib.rhs(0.0, x.data(), dxdt.data(), run.parameters);
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

// What the kernel and the settings must be for a contact run, checked before it starts.
void check_contact_run(const Run& run, const runtime::contact::ContactSystem<double>& sys, const State<double>& x) {
    const KernelLibrary& lib = run.lib;
    const RunSettings& s = run.settings;
    const std::string& scene = lib.scene_name();
    const SourcePos rows_pos{"[[unilateral]]"};
    if (!lib.constraint_names().empty() && !lib.has_constraint_rows())
        throw InputError(rows_pos, fmt::format("{}: the kernel has bilateral rows ({}) beside unilateral ones but no "
                                               "constraint_rows(); regenerate it with this eomc",
                                               scene, join(lib.constraint_names())));
    check_contact_settings(KernelShape{scene, sys.contacts.size(), lib.event_names()}, run.request, s);
    require_rates_are_velocities(run, x);
    for (std::size_t a = 0; a < sys.contacts.size(); ++a)
        if (!runtime::contact::valid_restitution(sys.contacts[a].restitution))
            throw InputError(rows_pos, fmt::format("{}: the restitution of {} is {}, outside [0, 1]", scene,
                                                   lib.contact_names()[a], number(sys.contacts[a].restitution)));
    std::vector<double> g0(sys.contacts.size());
    lib.gaps(0.0, x.data(), g0.data(), run.parameters);
    for (std::size_t a = 0; a < g0.size(); ++a) {
        const double slack = s.tolerances.atol + 1e-12 * (1.0 + std::abs(x[0]));
        if (!(g0[a] >= -slack))
            throw InputError(rows_pos, fmt::format("{}: the initial state violates the unilateral row {}: {} = {} < 0",
                                                   scene, lib.contact_names()[a],
                                                   lib.contact_kinematic()[a] ? "phi" : "f", number(g0[a])));
    }
}

// The contact run's recording: the rows' λ and active set beside every observed state, and each
// contact event in the result and as a labelled CSV row of the state after its transition.
class ContactRecording {
public:
    ContactRecording(const Run& run, Recorder& recorder, SimulationResult& result)
        : run_(run), recorder_(recorder), result_(result), lambda_(run.lib.contact_names().size(), 0.0),
          active_(lambda_.size(), false) {}

    void event(const runtime::contact::ContactEvent<double>& e) {
        ContactEventReport r;
        r.kind = std::string(runtime::contact::name(e.kind));
        r.name = run_.lib.contact_names()[e.contact];
        r.t = e.t;
        r.rate_before = e.rate_before;
        r.rate_after = e.rate_after;
        r.impulse = e.impulse;
        r.energy_change = e.energy_change;
        r.carnot = e.carnot;
        r.lambda = e.lambda;
        r.ratio = e.ratio;
        r.extrapolation_error = e.extrapolation_error;
        if (e.kind == runtime::contact::ContactEventKind::impact) ++result_.contacts[e.contact].impacts;
        if (e.kind == runtime::contact::ContactEventKind::impact || e.kind == runtime::contact::ContactEventKind::zeno)
            recorder_.jump();
        result_.contact_events.push_back(r);
        pending_.push_back(std::move(r));
    }

    // One CSV row labelled with the scene event `scene_event`; else one per pending contact event
    // at t (the state after its transition), or one plain row.
    void observe(double t, const State<double>& xs, const Vector& lambda, const std::vector<bool>& active,
                 const std::string* scene_event = nullptr) {
        std::uint64_t bits = 0;
        extra_.clear();
        for (std::size_t a = 0; a < lambda_.size(); ++a) {
            lambda_[a] = lambda[Eigen::Index(a)];
            active_[a] = active[a];
            extra_ += fmt::format(",{:.17g}", lambda_[a]);
            if (active_[a]) bits |= std::uint64_t(1) << a;
        }
        extra_ += fmt::format(",{}", bits);
        if (scene_event || pending_.empty()) return recorder_.record(t, xs, scene_event, extra_);
        for (const auto& e : pending_) {
            const std::string label = e.kind + ":" + e.name;
            recorder_.record(t, xs, &label, extra_);
        }
        pending_.clear();
    }

    // The rows' λ and active set at the end.
    void finish() {
        for (std::size_t a = 0; a < lambda_.size(); ++a) {
            result_.contacts[a].lambda = lambda_[a];
            result_.contacts[a].active = active_[a];
        }
    }

private:
    const Run& run_;
    Recorder& recorder_;
    SimulationResult& result_;
    std::vector<double> lambda_;
    std::vector<bool> active_;
    std::vector<ContactEventReport> pending_;
    std::string extra_;
};

// The event-driven driver with the request's adaptive dense-output stepper and the scene's events.
void run_event_driven(const Run& run, const runtime::contact::ContactSystem<double>& sys, State<double>& x,
                      ContactRecording& recording, SimulationResult& result) {
    const KernelLibrary& lib = run.lib;
    runtime::contact::EventDrivenOptions<double> options;
    options.detect_zeno = run.request.zeno_ratios > 0;
    options.zeno_ratios = std::max(1, run.request.zeno_ratios);
    options.impact_law = run.settings.impact_law;
    options.on_event = [&](const runtime::contact::ContactEvent<double>& e) { recording.event(e); };
    // The scene's [events], located on the driver's dense output, recorded like the other
    // drivers' (a CSV row labelled with the name, the state in the summary); terminal ones stop.
    for (std::size_t i = 0; i < lib.event_names().size(); ++i)
        options.events.push_back({static_cast<runtime::EventDirection>(lib.event_directions()[i]), lib.event_terminal()[i]});
    if (!options.events.empty()) {
        options.event_functions = [&](double t, const State<double>& xs, State<double>& h) {
            lib.events(t, xs.data(), h.data(), run.parameters);
        };
        options.on_scene_event = [&](const runtime::EventHit<double>& hit, const Vector& lambda,
                                     const std::vector<bool>& active) {
            const std::string& name = lib.event_names()[hit.index];
            recording.observe(hit.t, hit.x, lambda, active, &name);
            result.events.push_back({name, hit.t, hit.direction, hit.terminal, hit.x});
        };
    }
    const auto observer = [&](double t, const State<double>& xs, const Vector& lambda, const std::vector<bool>& active) {
        recording.observe(t, xs, lambda, active);
    };
    runtime::Limits limits;
    if (run.request.max_steps) limits.max_steps = *run.request.max_steps;
    runtime::contact::EventDrivenOutcome<double> outcome;
    runtime::visit_integrator<double>(run.settings.method->name, [&](auto tag) {
        using Stepper = typename decltype(tag)::type;
        if constexpr (runtime::AdaptiveStepper<Stepper> && runtime::DenseOutputStepper<Stepper>) {
            Stepper stepper;
            stepper.set_compensated(run.settings.compensated);
            outcome = runtime::contact::integrate_event_driven(stepper, sys, x, 0.0, run.request.t_end,
                                                               run.settings.tolerances, observer, options, limits);
        }
        return 0;
    });
    result.t = outcome.t;
    if (outcome.stopped) result.stopped_by = lib.event_names()[outcome.stopped_by];
    if (std::string w = unresolved_events_warning(outcome.unresolved, outcome.first_unresolved); !w.empty())
        result.warnings.push_back(std::move(w));
    result.steps = outcome.stats.accepted;
    result.rejected = outcome.stats.rejected;
    result.rhs_evals = outcome.stats.rhs_evals;
}

// Moreau–Jean's time stepping at the request's step and θ.
void run_moreau_jean(const Run& run, const runtime::contact::ContactSystem<double>& sys, State<double>& x,
                     ContactRecording& recording, SimulationResult& result) {
    const long steps = runtime::integrate_moreau_jean<double>(
        sys, 0.0, run.request.t_end, run.settings.step, run.settings.theta, x,
        [&](double t, const State<double>& xs, const Vector& lambda, const std::vector<bool>& active) {
            recording.observe(t, xs, lambda, active);
        },
        [&](const runtime::contact::ContactEvent<double>& e) { recording.event(e); });
    result.t = run.request.t_end;
    result.steps = std::size_t(steps);
    result.rhs_evals = 2 * std::size_t(steps);
}

}  // namespace

SimulationResult simulate_contacts(const Run& run, State<double>& x, SimulationResult result) {
    const KernelLibrary& lib = run.lib;
    const RunSettings& s = run.settings;
    const LibraryContactBlocks blocks{lib, run.parameters};
    const runtime::contact::ContactSystem<double> sys = runtime::contact::contact_system<double>(blocks);
    check_contact_run(run, sys, x);
    const bool event_driven = s.contact_method == ContactMethod::event_driven;
    result.contact_method = std::string(runtime::contact::name(s.contact_method));
    result.impact_law = std::string(runtime::contact::name(s.impact_law));
    if (!event_driven) result.integrator = fmt::format("moreau_jean (theta = {}, step {})", number(s.theta), number(s.step));
    for (std::size_t a = 0; a < sys.contacts.size(); ++a)
        result.contacts.push_back({lib.contact_names()[a], lib.contact_kinematic()[a], sys.contacts[a].restitution, 0.0,
                                   false, 0});

    std::vector<std::string> extra;
    for (const auto& name : lib.contact_names()) extra.push_back("lambda_" + name);
    extra.push_back("active");
    Recorder recorder(run, lib.state_names(), extra, true, x);
    ContactRecording recording(run, recorder, result);
    const auto start = std::chrono::steady_clock::now();
    try {
        if (event_driven) run_event_driven(run, sys, x, recording, result);
        else run_moreau_jean(run, sys, x, recording, result);
    } catch (const CsvOutput::RowLimit& limit) {
        throw recorder.row_limit(limit, runtime::contact::name(s.contact_method));
    } catch (const runtime::IntegrationError& e) {
        throw recorder.failed(e, s.method->name);
    }
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    recorder.finish(result.t, x, result);
    recording.finish();
    return result;
}

}  // namespace eomc::host
