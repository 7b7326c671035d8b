// simulate(): load the kernel, resolve the request, start from the scene's values with the
// overrides, and hand the run to the smooth or the contact driver.
#include <algorithm>

#include <fmt/format.h>

#include "host/simulate/runs.hpp"

namespace eomc::host {

namespace {

// An orbit kernel's re_entry event (g = r − radius, downwards) cannot see a start already below
// the surface: the generator refuses such a scene, and this refuses a --set that moves the start
// (or the radius) there.
void refuse_start_below_surface(const Run& run, const runtime::State<double>& x) {
    const auto& names = run.lib.event_names();
    const auto it = std::find(names.begin(), names.end(), "re_entry");
    if (it == names.end() || run.request.overrides.empty()) return;
    std::vector<double> g(names.size());
    run.lib.events(0.0, x.data(), g.data(), run.parameters);
    const double height = g[static_cast<std::size_t>(it - names.begin())];
    if (!(height > 0))
        throw InputError(SourcePos{"--set"},
                         fmt::format("the initial state of {} is {} km below the central body's surface "
                                     "(r − radius = {}): the run would start re-entered",
                                     run.lib.scene_name(), number(-height), number(height)));
}

}  // namespace

SimulationResult simulate(const SimulationRequest& request) {
    validate_request(request);  // before the compile: a typo costs none
    const KernelLibrary lib = KernelLibrary::load(request.header_text, request.struct_name, request.cache_dir);
    return simulate_loaded(request, lib);
}

SimulationResult simulate_loaded(const SimulationRequest& request, const KernelLibrary& lib) {
    const RunSettings settings = resolve_settings(request);
    std::vector<double> parameter_values;
    runtime::State<double> x;
    resolve_start(request, lib, parameter_values, x);
    const KernelLibrary::Parameters parameters = lib.make_parameters(parameter_values);
    const Run run{request, settings, lib, parameters};
    refuse_start_below_surface(run, x);

    SimulationResult result;
    result.scene_name = lib.scene_name();
    result.integrator = describe_method(settings);
    if (settings.method->uses_jacobian)
        result.integrator.insert(result.integrator.size() - 1, ", " + jacobian_source(run));  // inside the parentheses
    result.compensated = settings.compensated;
    result.compile_s = lib.seconds();
    result.cache_hit = lib.cache_hit();
    result.library_path = lib.library_path();
    for (std::size_t i = 0; i < parameter_values.size(); ++i)
        result.parameters.emplace_back(lib.parameter_names()[i], parameter_values[i]);
    if (!lib.contact_names().empty()) return simulate_contacts(run, x, std::move(result));
    return simulate_smooth(run, x, std::move(result));
}

}  // namespace eomc::host
