#include "host/orbit_bench.hpp"

#include <cmath>

#include <fmt/format.h>
#include <ginac/ginac.h>

#include "host/formulation_bench.hpp"
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
    r.axis = FormulationAxis{};  // Cowell's Cartesian position, its invariants, errors of 1, 1e-3, 1e-6
    const FormulationFamily orbit{scene::orbit_formulation_names, &FrontEndOptions::orbit_formulation,
                                  scene::check_orbit_formulation};
    const Pipeline cowell = add_formulations(r, scene_path, orbit, asked, orbit_formulation);
    r.axis.period = osculating_period(cowell.model);
}

}  // namespace eomc::host
