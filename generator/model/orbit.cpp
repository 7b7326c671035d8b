// The orbit kind ([orbit] and its [effects]; Mei, ch. 2): a point mass about a central body, its
// initial state, the kept perturbations and the formulation's domain.
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

namespace {

// The parameters each library effect reads, by fixed name (docs/scene-format.md).
struct EffectParameters {
    const char* effect;
    std::vector<std::pair<const char*, const char*>> parameters;  // name, meaning
};
const std::vector<EffectParameters>& orbit_effect_parameters() {
    static const std::vector<EffectParameters> table{
        {"J2", {{"J2", "the zonal coefficient J2"}}},
        {"J3", {{"J3", "the zonal coefficient J3"}}},
        {"J4", {{"J4", "the zonal coefficient J4"}}},
        {"drag",
         {{"rho0", "the density at the reference altitude, kg/m^3"},
          {"h0", "the reference altitude, km"},
          {"H", "the scale height, km"},
          {"CdA_m", "the ballistic coefficient Cd*A/m, m^2/kg"},
          {"omega", "the central body's (and its atmosphere's) rotation rate about z, rad/s"}}},
        {"third_body",
         {{"mu3", "the third body's gravitational parameter, km^3/s^2"},
          {"a3", "the radius of its circular orbit, km"},
          {"i3", "the inclination of its orbit to the x-y plane, radians"}}},
    };
    return table;
}

// Whether the formulation can start from this initial orbit. The model keeps these checks, the
// one piece of formulation knowledge it has, because they judge the scene's input: an error or
// a warning at the formulation key, reported by build_model with the scene's other input
// errors and warnings before anything is derived. Which elements each formulation integrates,
// and how, is mechanics/orbit's.
void check_formulation_domain(const Orbit& orbit, const std::array<double, 6>& x0, double mu,
                              const SourcePos& initial_pos, std::vector<Warning>& warnings) {
    using enum scene::OrbitFormulationKind;
    switch (orbit.kind) {
        case cowell:
        case equinoctial: return;  // any conic (equinoctial: singular only at i = 180°, never refused)
        case encke: {
            // The reference is a Kepler ellipse (its position is written through E = kepler_E(M, e)).
            const double r0 = std::hypot(x0[0], x0[1], x0[2]);
            const double energy = (x0[3] * x0[3] + x0[4] * x0[4] + x0[5] * x0[5]) / 2 - mu / r0;
            if (!(energy < 0))
                throw InputError(orbit.formulation_pos,
                                 fmt::format("the encke formulation needs an elliptic initial orbit (its reference is "
                                             "a Kepler ellipse), but this one has specific energy {} ≥ 0 ({}); use "
                                             "cowell or equinoctial",
                                             energy, energy == 0 ? "a parabola" : "a hyperbola"));
            return;
        }
        case gauss:
        case lagrange:
        case delaunay:
        case mean: break;
    }
    // The classical elements' equations carry 1/e (ω̇, Ṁ) and 1/sin i (Ω̇, i̇): exactly there they
    // are undefined, near there the perturbation's effect on ω and Ω is amplified by 1/e or
    // 1/sin i and the angles turn fast while their sums stay smooth (Vallado, Fundamentals of
    // Astrodynamics and Applications, 4th ed., §9.6).
    const std::string_view kind = scene::name(orbit.kind);
    runtime::ClassicalElements<double> el{};
    try {
        el = runtime::classical_from_cartesian(runtime::CartesianState<double>{x0[0], x0[1], x0[2], x0[3], x0[4], x0[5]},
                                               mu);
    } catch (const runtime::KeplerError& e) {
        throw InputError(initial_pos, fmt::format("the orbit has no classical elements: {}", e.what()));
    }
    const double sin_i = std::sin(el.i);
    constexpr double exactly = 1e-12, near = 1e-3;  // near: a thousandfold amplification
    if (el.e < exactly || sin_i < exactly)
        throw InputError(orbit.formulation_pos,
                         fmt::format("the {} formulation's elements are singular for this orbit ({}): its "
                                     "equations divide by e and sin i; use formulation = \"equinoctial\" "
                                     "(non-singular at e = 0 and i = 0) or \"cowell\"",
                                     kind, el.e < exactly ? "circular, e = 0" : "equatorial, sin i = 0"));
    if (el.e < near || sin_i < near)
        warnings.push_back(
            {orbit.formulation_pos,
             fmt::format("the {} formulation's elements are nearly singular for this orbit (e = {:.3g}, i = "
                         "{:.3g}°): its equations divide by e and sin i, so ω and Ω turn fast and steps shrink; "
                         "formulation = \"equinoctial\" is non-singular at e = 0 and i = 0",
                         kind, el.e, el.i * 180 / std::numbers::pi)});
}

}  // namespace

// [orbit] and an orbit scene's [effects]: coordinates x, y, z with the initial state, T, V and
// the non-conservative accelerations. Each library effect is only its potential or its
// acceleration; the equations follow by differentiation like any other scene's.
void build_orbit(const scene::Scene& scene, SymbolTable& symbols, Model& model) {
    const scene::Orbit& given = *scene.orbit;
    Orbit orbit;
    orbit.kind = given.formulation;
    orbit.formulation_pos = given.formulation_pos.file.empty() ? given.pos : given.formulation_pos;
    orbit.rectify = given.rectify;
    orbit.mu = symbols.parse(given.mu, unsigned(SymbolKind::parameter), "the central body's mu");
    orbit.radius = symbols.parse(given.radius, unsigned(SymbolKind::parameter), "the central body's radius");
    const double mu = at_defaults(orbit.mu, model, given.mu, "the central body's mu");
    if (!(mu > 0)) throw InputError(given.mu.pos, fmt::format("the central body's mu must be positive, got {}", mu));
    orbit.mu_default = mu;
    if (!(at_defaults(orbit.radius, model, given.radius, "the central body's radius") > 0))
        throw InputError(given.radius.pos, "the central body's radius must be positive");

    // The initial state: given, or from classical elements by the runtime's own conversion.
    std::array<double, 6> x0{};
    if (given.state) {
        x0 = *given.state;
    } else {
        const auto& el = *given.elements;
        try {
            x0 = runtime::cartesian_from_classical(runtime::ClassicalElements<double>{el[0], el[1], el[2], el[3], el[4], el[5]},
                                                   mu);
        } catch (const runtime::KeplerError& e) {
            throw InputError(given.initial_pos, fmt::format("the orbit's elements give no state: {}", e.what()));
        }
    }
    const char* names[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k)
        model.coordinates.push_back({names[k], symbols.declare(names[k], SymbolKind::coordinate),
                                     symbols.declare(std::string(names[k]) + "_dot", SymbolKind::velocity),
                                     symbols.declare(std::string(names[k]) + "_ddot", SymbolKind::acceleration),
                                     x0[std::size_t(k)], x0[std::size_t(k) + 3]});
    const ex x = model.coordinates[0].q, y = model.coordinates[1].q, z = model.coordinates[2].q;
    const ex vx = model.coordinates[0].q_dot, vy = model.coordinates[1].q_dot, vz = model.coordinates[2].q_dot;
    const ex r = GiNaC::sqrt(x * x + y * y + z * z);
    orbit.r = r;
    // Below the surface the model means nothing (drag grows without bound, r → 0 is singular).
    const double radius = at_defaults(orbit.radius, model, given.radius, "the central body's radius");
    if (!(std::hypot(x0[0], x0[1], x0[2]) > radius))
        throw InputError(given.initial_pos,
                         fmt::format("the orbit starts at r = {} km, at or below the central body's surface (radius {})",
                                     std::hypot(x0[0], x0[1], x0[2]), radius));

    check_formulation_domain(orbit, x0, mu, given.initial_pos, model.warnings);

    // Each kept effect's parameters, found by name; a missing one is an error at the effect.
    auto parameter = [&](const std::string& effect, const SourcePos& pos, const char* name) -> ex {
        for (const auto& p : model.parameters)
            if (p.name == name) return p.symbol;
        std::string meaning;
        std::string all;
        for (const auto& e : orbit_effect_parameters())
            if (effect == e.effect)
                for (const auto& [n, m] : e.parameters) {
                    if (std::string(n) == name) meaning = m;
                    all += (all.empty() ? "" : ", ") + std::string(n);
                }
        throw InputError(pos, fmt::format("effect '{}' needs the parameter '{}' ({}), which [parameters] does not "
                                          "declare (the effect reads: {})",
                                          effect, name, meaning, all));
    };
    const ex& Re = orbit.radius;
    const ex s = z / r;
    for (std::size_t k = 0; k < scene.effects.keep.size(); ++k) {
        const std::string& e = scene.effects.keep[k];
        const SourcePos& pos = scene.effects.keep_pos[k];
        auto P = [&](const char* name) { return parameter(e, pos, name); };
        // Zonal harmonics: U = (μ/r)[1 − Σ J_n (R_e/r)^n P_n(z/r)], so R_n = −(μ/r) J_n (R_e/r)^n P_n
        // (Vallado, Fundamentals of Astrodynamics and Applications, eq. 8-19; Mei, ch. 2).
        if (e == "J2") {
            orbit.disturbing.push_back({e, -orbit.mu / r * P("J2") * GiNaC::pow(Re / r, 2) * (3 * s * s - 1) / 2});
        } else if (e == "J3") {
            orbit.disturbing.push_back(
                {e, -orbit.mu / r * P("J3") * GiNaC::pow(Re / r, 3) * (5 * GiNaC::pow(s, 3) - 3 * s) / 2});
        } else if (e == "J4") {
            orbit.disturbing.push_back(
                {e, -orbit.mu / r * P("J4") * GiNaC::pow(Re / r, 4) * (35 * GiNaC::pow(s, 4) - 30 * s * s + 3) / 8});
        } else if (e == "third_body") {
            // A third body on a circular orbit of radius a3 inclined by i3 (node on x), mean motion
            // n3 = √((μ + μ3)/a3³), at the node at t = 0. Direct and indirect terms:
            // R = μ3 (1/|r3 − r| − r·r3/|r3|³).
            const ex mu3 = P("mu3"), a3 = P("a3"), i3 = P("i3");
            const ex n3 = GiNaC::sqrt((orbit.mu + mu3) / GiNaC::pow(a3, 3));
            const ex u = n3 * model.t;
            const ex x3 = a3 * GiNaC::cos(u), y3 = a3 * GiNaC::cos(i3) * GiNaC::sin(u), z3 = a3 * GiNaC::sin(i3) * GiNaC::sin(u);
            const ex d = GiNaC::sqrt(GiNaC::pow(x3 - x, 2) + GiNaC::pow(y3 - y, 2) + GiNaC::pow(z3 - z, 2));
            orbit.disturbing.push_back({e, mu3 * (1 / d - (x * x3 + y * y3 + z * z3) / GiNaC::pow(a3, 3))});
        } else if (e == "drag") {
            // Exponential atmosphere co-rotating with the body at ω about z: v_rel = v − ω ẑ × r,
            // a = −½ ρ(h) (Cd A/m) |v_rel| v_rel, h = r − R_e. ρ in kg/m³ times Cd A/m in m²/kg is
            // per metre; the factor 1000 m/km makes it per km, the scene's length unit.
            const ex rho0 = P("rho0"), h0 = P("h0"), H = P("H"), B = P("CdA_m"), w = P("omega");
            const ex rho = rho0 * GiNaC::exp(-(r - Re - h0) / H);
            const Vec3 v_rel{vx + w * y, vy - w * x, vz};
            const ex speed = GiNaC::sqrt(v_rel[0] * v_rel[0] + v_rel[1] * v_rel[1] + v_rel[2] * v_rel[2]);
            const ex k = -ex(1000) / 2 * rho * B * speed;
            orbit.accelerations.push_back({e, {k * v_rel[0], k * v_rel[1], k * v_rel[2]}});
        }
    }
    if (scene.effects.disturbing_function)
        orbit.disturbing.push_back({"custom", symbols.parse(*scene.effects.disturbing_function, configuration,
                                                            "the custom disturbing function R(x, y, z, t)")});
    if (scene.effects.acceleration)
        orbit.accelerations.push_back(
            {"custom", parse_vector(symbols, *scene.effects.acceleration, phase, "the custom acceleration")});
    for (const auto& term : orbit.disturbing) orbit.R += term.value;
    for (const auto& a : orbit.accelerations)
        for (int i = 0; i < 3; ++i) orbit.acceleration[std::size_t(i)] += a.value[std::size_t(i)];

    model.kinetic_energy = (vx * vx + vy * vy + vz * vz) / 2;
    model.potential = -orbit.mu / r - orbit.R;
    model.kinetic_pos = given.pos;
    model.orbit = std::move(orbit);
}

}  // namespace eomc::model
