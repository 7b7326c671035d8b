#include "host/orbit_bench.hpp"

#include <cmath>

#include <fmt/format.h>
#include <ginac/ginac.h>

#include "host/pipeline.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace eomc::host {

namespace {

// The period 2π √(a³/μ) of the initial osculating ellipse (0 when it is no ellipse), with a from
// the vis-viva equation 1/a = 2/r − v²/μ (Battin, An Introduction to the Mathematics and Methods
// of Astrodynamics, 1999, eq. 3.20), from Cowell's initial state and μ at the parameters' defaults.
double osculating_period(const model::Model& m) {
    if (!m.orbit || m.coordinates.size() != 3) return 0.0;
    GiNaC::lst defaults;
    for (const auto& par : m.parameters) defaults.append(par.symbol == par.value);
    const GiNaC::ex mu = GiNaC::evalf(m.orbit->mu.subs(defaults));
    if (!GiNaC::is_a<GiNaC::numeric>(mu)) return 0.0;
    const double gm = GiNaC::ex_to<GiNaC::numeric>(mu).to_double();
    double r2 = 0, v2 = 0;
    for (const auto& c : m.coordinates) r2 += c.initial * c.initial, v2 += c.rate * c.rate;
    const double inverse_a = 2.0 / std::sqrt(r2) - v2 / gm;
    if (!(gm > 0.0 && inverse_a > 0.0)) return 0.0;
    return 2.0 * M_PI * std::sqrt(1.0 / (inverse_a * inverse_a * inverse_a) / gm);
}

}  // namespace

void add_orbit_formulations(BenchRequest& r, const std::string& scene_path, const std::vector<std::string>& asked,
                            const std::string& orbit_formulation) {
    std::vector<std::string> names = asked;
    if (names.empty() && !orbit_formulation.empty()) names = {orbit_formulation};
    if (names.empty()) names.assign(scene::orbit_formulation_names.begin(), scene::orbit_formulation_names.end());
    for (const auto& name : names) scene::check_orbit_formulation(name, SourcePos{"--formulations"});
    const auto formulation = [&](const std::string& name) {
        FrontEndOptions options;
        options.orbit_formulation = name;
        options.flag = "--formulations";
        return front_end(scene_path, options);
    };
    const Pipeline cowell = formulation("cowell");
    r.header_text = kernel_header(cowell);
    r.struct_name = cowell.model.struct_name;
    r.scene_name = scene::parse_scene_file(scene_path).name;  // not a formulation's kernel name
    r.reference_body.clear();
    r.orbit_period = osculating_period(cowell.model);
    const bool all_built = asked.empty() && orbit_formulation.empty();
    for (const auto& name : names) {
        try {
            const Pipeline f = name == "cowell" ? cowell : formulation(name);
            r.formulations.push_back({name, name == "cowell" ? r.header_text : kernel_header(f), f.model.struct_name,
                                      f.model.name, !depends_on_time(f)});
        } catch (const InputError& e) {
            // Asked for by name: bad input. Among "all built": a formulation that does not take
            // this scene (mean with drag) is left out, and the table says why.
            if (!all_built) throw;
            r.skipped.push_back(fmt::format("{}: left out: {}", name, e.message()));
        }
    }
    if (r.formulations.empty())
        throw InputError(SourcePos{"--formulations"},
                         "no formulation takes this scene: " + fmt::format("{}", fmt::join(r.skipped, "; ")));
}

}  // namespace eomc::host
