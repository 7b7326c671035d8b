#include "mechanics/orbit/formulation.hpp"

#include <array>
#include <string>

#include <fmt/format.h>

#include "mechanics/orbit/element_formulations.hpp"
#include "mechanics/orbit/encke.hpp"
#include "mechanics/orbit/equinoctial.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

namespace {

using K = OrbitFormulationKind;

constexpr std::array<std::string_view, 6> cartesian{"x", "y", "z", "x_dot", "y_dot", "z_dot"};
constexpr std::array<std::string_view, 6> classical{"a", "e", "i", "raan", "argp", "mean_anomaly"};
constexpr std::array<std::string_view, 6> delaunay{"l", "g", "h", "L", "G", "H"};
constexpr std::array<std::string_view, 6> equinoctial{"p", "f", "g", "h", "k", "L"};
// The deviation δ = r − ρ and its rate, the reference orbit's epoch and classical elements at
// that epoch (constant between rectifications), and the number of rectifications so far.
constexpr std::array<std::string_view, 14> encke{"dx",     "dy",       "dz",       "dx_dot", "dy_dot",
                                                 "dz_dot", "ref_t",    "ref_a",    "ref_e",  "ref_i",
                                                 "ref_raan", "ref_argp", "ref_M", "rectifications"};

// In OrbitFormulationKind order (tests/mechanics/orbit checks each entry's kind and name).
const std::array<OrbitFormulation, 7> registry{{
    {K::cowell, scene::name(K::cowell),
     "Cowell: Newton's equations in inertial Cartesian x, y, z (Lagrange's equations of T = |v|²/2, V = −μ/r − R)",
     cartesian, false, lagrange_form, true, true},
    {K::encke, scene::name(K::encke),
     "Encke: the deviation from a reference Kepler ellipse, rectified when it grows (Battin §9.3)", encke, false,
     encke_form, false, false},
    {K::lagrange, scene::name(K::lagrange),
     "Lagrange's planetary equations for the classical elements in the partials of R (Brouwer & Clemence ch. XI)",
     classical, false, lagrange_planetary_form, false, true},
    {K::gauss, scene::name(K::gauss),
     "Gauss's equations for the classical elements in the perturbing acceleration's r, t, n components (Vallado "
     "eq. 9-24)",
     classical, false, gauss_form, false, true},
    {K::delaunay, scene::name(K::delaunay),
     "The canonical equations of the Delaunay variables, K = −μ²/(2L²) − R (Brouwer 1959)", delaunay, false,
     delaunay_form, false, true},
    {K::equinoctial, scene::name(K::equinoctial),
     "Gauss's equations for the modified equinoctial elements, regular at e = 0 and i = 0 (Walker, Ireland & Owens "
     "1985)",
     equinoctial, true, equinoctial_form, false, true},
    {K::mean, scene::name(K::mean),
     "Lagrange's equations in R averaged over the mean anomaly: the secular motion of the mean elements (Kozai 1959)",
     classical, false, mean_elements_form, false, true},
}};

}  // namespace

const OrbitFormulation& orbit_formulation(OrbitFormulationKind kind) { return registry.at(static_cast<std::size_t>(kind)); }

std::span<const OrbitFormulation> orbit_formulations() { return registry; }

bool hamiltonian_applies(OrbitFormulationKind kind) { return orbit_formulation(kind).hamiltonian; }

bool variational_applies(OrbitFormulationKind kind) { return orbit_formulation(kind).variational; }

void check_state_names_free(const model::Model& model) {
    const model::Orbit& o = *model.orbit;
    const OrbitFormulation& f = orbit_formulation(o.kind);
    if (!f.reserves_state_names) return;
    for (const auto& p : model.parameters)
        for (const std::string_view element : f.state_names)
            if (p.name == element)
                throw InputError(o.formulation_pos,
                                 fmt::format("the {} formulation's state has an element '{}', which names a "
                                             "parameter of this scene; rename the parameter",
                                             f.name, element));
}

}  // namespace eomc::mechanics
