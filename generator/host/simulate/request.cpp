// The request resolved to the runtime's types and checked once, before anything is compiled; the
// start state with the request's overrides.
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"
#include "host/simulate/output.hpp"
#include "support/diagnostic.hpp"
#include "support/output_file.hpp"

namespace eomc::host {

namespace {

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

// What a table found for `name`, or an InputError at `where` naming the nearest of its names.
template <class T>
T choose(const std::optional<T>& found, const std::string& name, const std::vector<std::string>& names,
         const SourcePos& where, const char* what) {
    if (found) return *found;
    const std::string near = nearest_name(name, names);
    throw InputError(where, fmt::format("unknown {} '{}'{} (expected one of {})", what, name,
                                        near.empty() ? "" : "; did you mean '" + near + "'?", join(names)));
}

// The one rule for a length of time or a tolerance: positive and finite.
void require_positive(double value, const SourcePos& where, const std::string& what) {
    if (!(std::isfinite(value) && value > 0.0))
        throw InputError(where, fmt::format("{} must be positive and finite, not {}", what, value));
}

}  // namespace

void check_fixed_step_budget(const SimulationRequest& r, std::string_view method, double step) {
    // Known before the run: refuse it now rather than after hours, or after a disk is full.
    const double steps = std::ceil(r.t_end / step);
    const std::size_t budget = r.max_steps.value_or(SimulationRequest::default_max_fixed_steps);
    if (steps > static_cast<double>(budget))
        throw InputError(SourcePos{"--step"},
                         fmt::format("{} with step {} to t_end = {} takes {:.3g} steps, more than the budget of {} "
                                     "(--max-steps); take a larger step or a shorter run, or raise --max-steps",
                                     method, step, r.t_end, steps, budget));
    if (!r.csv_path.empty() && steps + 1.0 > static_cast<double>(r.max_rows))
        throw InputError(SourcePos{"--output"},
                         fmt::format("the CSV {} would hold {:.3g} rows (one per step), more than the limit of {} "
                                     "(--max-rows); take a larger step or a shorter run, or raise --max-rows",
                                     r.csv_path, steps + 1.0, r.max_rows));
}

RunSettings resolve_settings(const SimulationRequest& r) {
    namespace rc = runtime::contact;
    RunSettings s;
    const runtime::IntegratorInfo* method = runtime::find_integrator(r.integrator);
    s.method = choose(method ? std::optional(method) : std::nullopt, r.integrator,
                       runtime::integrator_names_where([](const auto&) { return true; }), r.integrator_pos,
                       "integrator");
    s.contact_method = choose(rc::find_contact_method(r.contact_method), r.contact_method, rc::contact_method_names(),
                              r.contact_method_pos, "contact method");
    s.impact_law =
        choose(rc::find_impact_law(r.impact_law), r.impact_law, rc::impact_law_names(), r.impact_law_pos, "impact law");
    require_positive(r.t_end, SourcePos{"--t-end"}, "the end time");
    if (s.method->fixed_step()) {
        require_positive(r.step, SourcePos{"--step"}, fmt::format("the {} step", r.integrator));
    } else {
        require_positive(r.rtol, SourcePos{"--rtol"}, "the relative tolerance");
        require_positive(r.atol, SourcePos{"--atol"}, "the absolute tolerance");
    }
    if (r.max_steps && *r.max_steps == 0) throw InputError(SourcePos{"--max-steps"}, "the step budget must be at least 1");
    if (s.method->fixed_step()) check_fixed_step_budget(r, r.integrator, r.step);
    if (!rc::valid_theta(r.theta))
        throw InputError(r.contact_method_pos, fmt::format("theta must lie in [0.5, 1], not {}", r.theta));
    if (r.summary_format != "text" && r.summary_format != "json")
        throw InputError(SourcePos{"--summary"},
                         fmt::format("unknown summary format '{}' (expected text or json)", r.summary_format));
    s.tolerances = runtime::Tolerances{r.rtol, r.atol};
    s.step = r.step;
    s.compensated = r.compensated.value_or(s.method->compensated_by_default);
    s.theta = r.theta;
    return s;
}

void validate_request(const SimulationRequest& request) {
    (void)resolve_settings(request);
    if (!request.csv_path.empty()) check_output_target(request.csv_path);
}

void check_contact_settings(const KernelShape& kernel, const SimulationRequest& r, const RunSettings& s) {
    if (kernel.contacts == 0) return;
    const std::string& scene = kernel.scene_name;
    const bool event_driven = s.contact_method == runtime::contact::ContactMethod::event_driven;
    if (!kernel.event_names.empty() && !event_driven)
        throw InputError(r.contact_method_pos,
                         fmt::format("{}: scene events ({}) together with unilateral rows need contact method "
                                     "event_driven; moreau_jean does not locate them yet",
                                     scene, join(kernel.event_names)));
    if (r.variational)
        throw InputError(SourcePos{"--variational"}, fmt::format("{}: the state-transition matrix is not defined "
                                                                 "across impacts; run without --variational", scene));
    if (kernel.contacts > 64)
        throw InputError(SourcePos{"[[unilateral]]"},
                         fmt::format("{}: {} unilateral rows; the CSV's active-set bitmask holds 64", scene, kernel.contacts));
    if (!event_driven && s.impact_law == runtime::contact::ImpactLaw::sequential)
        throw InputError(r.impact_law_pos, fmt::format("{}: the sequential impact law needs contact method "
                                                       "event_driven; Moreau-Jean resolves every step's "
                                                       "impacts simultaneously",
                                                       scene));
    if (!event_driven) {
        require_positive(s.step, SourcePos{"--step"}, "the moreau_jean step");
        check_fixed_step_budget(r, "moreau_jean", s.step);
    } else if (s.method->fixed_step() || !s.method->dense_output) {
        throw InputError(r.integrator_pos,
                         fmt::format("{}: the event-driven contact method needs an adaptive integrator with dense "
                                     "output ({}), not {}; or use contact method moreau_jean",
                                     scene,
                                     runtime::integrator_list(
                                         [](const auto& i) { return !i.fixed_step() && i.dense_output; }, ", ", " or "),
                                     s.method->name));
    }
}

std::string describe_method(const RunSettings& s, bool show_compensated) {
    const char* compensated = show_compensated && s.compensated ? ", compensated" : "";
    return s.method->fixed_step()
               ? fmt::format("{} (step {}{})", s.method->name, s.step, compensated)
               : fmt::format("{} (rtol {}, atol {}{})", s.method->name, s.tolerances.rtol, s.tolerances.atol,
                             compensated);
}

void check_separable(const runtime::IntegratorInfo& method, const SourcePos& where, bool separable,
                     const std::string& scene_name) {
    if (method.needs_separable && !separable)
        throw InputError(where, fmt::format("the {} integrator needs a separable system (q̈ = a(t, q) with a constant "
                                            "mass matrix, forces free of the velocities, no constraint rows), and {} "
                                            "is not one; use {} "
                                            "for a symplectic fixed-step method",
                                            method.name, scene_name,
                                            runtime::integrator_list([](const runtime::IntegratorInfo& i) {
                                                return i.symplectic && !i.needs_separable;
                                            }, ", ", " or ")));
}

// --set NAME=VALUE: a parameter, or the initial value of a state component ("q", "q_dot").
void resolve_start(const SimulationRequest& r, const KernelLibrary& lib, std::vector<double>& parameters,
                   std::vector<double>& x) {
    parameters = lib.parameter_defaults();
    x.assign(lib.initial_state().begin(), lib.initial_state().end());
    const SourcePos where{"--set"};
    // Initial values the scene gives as expressions of the parameters follow the overrides' values.
    std::vector<std::pair<std::string, double>> all = r.overrides;
    if (r.derived_start && !r.overrides.empty()) {
        const auto derived = r.derived_start(r.overrides);
        all.insert(all.end(), derived.begin(), derived.end());
    }
    for (const auto& [name, value] : all) {
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
        // As --set refuses it (support/decimal.cpp): the start's checks and the scene's exact
        // arithmetic hand values to CLN, which has no subnormal floats ("floating point underflow").
        if (value != 0 && std::abs(value) < std::numeric_limits<double>::min())
            throw InputError(where, fmt::format("{}={}: a subnormal value (below 2.2e-308 in magnitude), which eomc's "
                                                "exact arithmetic cannot hold",
                                                name, value));
        (p >= 0 ? parameters[static_cast<std::size_t>(p)] : x[static_cast<std::size_t>(s)]) = value;
    }
    if (r.check_start && !r.overrides.empty()) r.check_start(r.overrides);
}

}  // namespace eomc::host
