#include "model/model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <numbers>
#include <random>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "eomc/runtime/rigid/andoyer_deprit.hpp"
#include "model/expression_parser.hpp"
#include "support/diagnostic.hpp"
#include "support/identifier.hpp"

namespace eomc::model {

using GiNaC::ex;

const char* name(Effect e) {
    switch (e) {
        case Effect::relative: return "relative";
        case Effect::translation: return "translation";
        case Effect::euler: return "euler";
        case Effect::centrifugal: return "centrifugal";
        case Effect::coriolis: return "coriolis";
    }
    return "?";
}

GiNaC::lst Model::state_symbols() const {
    GiNaC::lst out{t};
    for (const auto& c : coordinates) out.append(c.q);
    for (const auto& c : coordinates) out.append(c.q_dot);
    for (const auto& v : quasi_velocities) out.append(v.symbol);
    if (rigid) {
        for (std::size_t i = 0; i < 3; ++i) out.append(rigid->omega[i]).append(rigid->gamma[i]);
        if (rigid->attitude)
            for (const auto& e : *rigid->attitude) out.append(e);
    }
    for (const auto& p : parameters) out.append(p.symbol);
    return out;
}

std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> RigidBody::attitude_rates() const {
    std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> out;
    const Vec3 g = gamma_vector(), w = omega_vector();
    // γ̇ = γ × ω (Poisson).
    out.emplace_back(gamma[0], g[1] * w[2] - g[2] * w[1]);
    out.emplace_back(gamma[1], g[2] * w[0] - g[0] * w[2]);
    out.emplace_back(gamma[2], g[0] * w[1] - g[1] * w[0]);
    if (attitude) {
        // ė = ½ e ⊗ (0, ω), ω in body axes (Kuipers, Quaternions and Rotation Sequences, 1999, §11.5).
        const auto& [e0, e1, e2, e3] = *attitude;
        const GiNaC::ex half = GiNaC::numeric(1, 2);
        out.emplace_back(e0, -half * (e1 * w[0] + e2 * w[1] + e3 * w[2]));
        out.emplace_back(e1, half * (e0 * w[0] + e2 * w[2] - e3 * w[1]));
        out.emplace_back(e2, half * (e0 * w[1] + e3 * w[0] - e1 * w[2]));
        out.emplace_back(e3, half * (e0 * w[2] + e1 * w[1] - e2 * w[0]));
    }
    return out;
}

GiNaC::exmap Model::parameter_defaults() const {
    GiNaC::exmap defaults;
    for (const auto& p : parameters) defaults[p.symbol] = GiNaC::numeric(p.value);
    return defaults;
}

std::vector<std::string> Model::velocity_names() const {
    std::vector<std::string> names;
    for (const auto& c : coordinates) names.push_back(c.name);
    for (const auto& v : quasi_velocities) names.push_back(v.name);
    return names;
}

namespace {

constexpr unsigned time_and_parameters = SymbolKind::time | SymbolKind::parameter;
constexpr unsigned configuration = time_and_parameters | SymbolKind::coordinate;
constexpr unsigned phase = configuration | SymbolKind::velocity;

Vec3 parse_vector(const SymbolTable& symbols, const scene::Vec3& v, unsigned allowed, const std::string& what) {
    return {symbols.parse(v[0], allowed, what), symbols.parse(v[1], allowed, what),
            symbols.parse(v[2], allowed, what)};
}

// e at `values` as a real float, or nothing where it is undefined there: GiNaC throws when the
// values reach a pole (log(0), 1/0) and leaves a non-numeric or complex value otherwise.
std::optional<GiNaC::numeric> real_value(const ex& e, const GiNaC::exmap& values) {
    try {
        const ex value = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
        if (GiNaC::is_a<GiNaC::numeric>(value) && GiNaC::ex_to<GiNaC::numeric>(value).is_real())
            return GiNaC::ex_to<GiNaC::numeric>(value);
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

// A mass must be a positive constant: evaluate it at the parameters' defaults.
ex parse_mass(const SymbolTable& symbols, const scene::Body& body, const Model& model) {
    const std::string what = fmt::format("the mass of body '{}'", body.name);
    ex mass = symbols.parse(body.mass, unsigned(SymbolKind::parameter), what);
    const auto value = real_value(mass, model.parameter_defaults());
    if (!value) throw InputError(body.mass.pos, fmt::format("{} does not evaluate to a real number", what));
    if (value->to_double() <= 0.0)
        throw InputError(body.mass.pos, fmt::format("{} must be positive, but '{}' = {} with the default parameters",
                                                    what, body.mass.text, value->to_double()));
    return mass;
}

// 3 principal moments or 9 entries → a symmetric 3×3 matrix of constants.
GiNaC::matrix parse_inertia(const SymbolTable& symbols, const std::vector<scene::Expr>& entries, const SourcePos& pos,
                            const std::string& what) {
    GiNaC::matrix I(3, 3);
    for (std::size_t k = 0; k < entries.size(); ++k) {
        const ex value = symbols.parse(entries[k], unsigned(SymbolKind::parameter), what);
        if (entries.size() == 3) I(unsigned(k), unsigned(k)) = value;
        else I(unsigned(k / 3), unsigned(k % 3)) = value;
    }
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = i + 1; j < 3; ++j)
            if (!(I(i, j) - I(j, i)).expand().is_zero())
                throw InputError(pos, fmt::format("{} is not symmetric: entry ({},{}) differs from ({},{})", what, i + 1,
                                                  j + 1, j + 1, i + 1));
    return I;
}

// The carrier's own mass distribution (required for a free carrier, optional for a prescribed
// one) and the loads [forces] resultant and moment on its system.
void add_carrier_mass_and_loads(const scene::Carrier& c, const scene::Forces& forces, const SymbolTable& symbols,
                                const Model& model, Carrier& carrier) {
    if (c.mass) {
        scene::Body as_body{"carrier", *c.mass, {}, {}, {}, c.pos, {}, {}};
        carrier.mass = parse_mass(symbols, as_body, model);
    }
    carrier.inertia = parse_inertia(symbols, c.inertia, c.pos, "the carrier's inertia");
    carrier.center = parse_vector(symbols, c.center, unsigned(SymbolKind::parameter), "the carrier's mass centre");
    // The applied loads may depend on the whole motion (a damper, a motor law).
    const unsigned loads = phase;
    if (forces.resultant) carrier.resultant = parse_vector(symbols, *forces.resultant, loads, "the resultant force");
    if (forces.moment) carrier.moment = parse_vector(symbols, *forces.moment, loads, "the resultant moment");
}

// A free carrier: each component of v_o and ω is a new name (an unknown quasi-velocity) or
// "0" (held by the constraints); anything else is an error at that component.
void build_free_carrier(const scene::Carrier& c, const scene::Forces& forces, SymbolTable& symbols, Model& model) {
    Carrier carrier;
    carrier.free = true;
    std::map<std::string, SourcePos> declared;
    for (const bool angular : {false, true}) {
        const scene::Vec3& v = angular ? c.angular_velocity : c.pole_velocity;
        Vec3& out = angular ? carrier.angular_velocity : carrier.pole_velocity;
        for (int axis = 0; axis < 3; ++axis) {
            const scene::Expr& e = v[std::size_t(axis)];
            if (e.text == "0") {
                out[std::size_t(axis)] = 0;
                continue;
            }
            const bool identifier = is_scene_identifier(e.text);
            const std::string what = angular ? "angular_velocity" : "pole_velocity";
            if (!identifier)
                throw InputError(e.pos, fmt::format("a free carrier's {} component must be a new name (an unknown "
                                                    "quasi-velocity) or \"0\" (held by the constraints), got '{}'",
                                                    what, e.text));
            if (symbols.contains(e.text) || symbols.contains(e.text + "_dot") || declared.count(e.text))
                throw InputError(e.pos, fmt::format("the quasi-velocity '{}' clashes with a name already declared "
                                                    "(it needs '{}' and '{}_dot' to be free)",
                                                    e.text, e.text, e.text));
            declared.emplace(e.text, e.pos);
            QuasiVelocity q{e.text, symbols.declare(e.text, SymbolKind::velocity),
                            symbols.declare(e.text + "_dot", SymbolKind::acceleration), 0.0, angular, axis};
            out[std::size_t(axis)] = q.symbol;
            model.quasi_velocities.push_back(std::move(q));
        }
    }
    for (const auto& init : c.initial) {
        auto it = std::find_if(model.quasi_velocities.begin(), model.quasi_velocities.end(),
                               [&](const QuasiVelocity& q) { return q.name == init.name; });
        if (it == model.quasi_velocities.end()) {
            std::vector<std::string> names;
            for (const auto& q : model.quasi_velocities) names.push_back(q.name);
            const std::string near = nearest_name(init.name, names);
            throw InputError(init.pos, fmt::format("'{}' in [carrier.initial] is not a quasi-velocity of the carrier{}",
                                                   init.name, near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        it->initial = init.value;
    }
    add_carrier_mass_and_loads(c, forces, symbols, model, carrier);
    model.carrier = std::move(carrier);
}

// [newtonian]: one equation per coordinate, each naming a declared coordinate once; the
// fundamental form must be affine in the accelerations (A q̈ + B).
Newtonian build_newtonian(const SymbolTable& symbols, const scene::Newtonian& given, const Model& model) {
    Newtonian n;
    n.fundamental = given.fundamental;
    n.pos = given.pos;
    const std::size_t count = model.coordinates.size();
    n.expressions.assign(count, ex(0));
    n.positions.assign(count, given.pos);
    std::vector<bool> seen(count, false);
    std::vector<std::string> names;
    for (const auto& c : model.coordinates) names.push_back(given.fundamental ? c.name : c.name + "_ddot");
    for (const auto& eq : given.equations) {
        const std::string key = given.fundamental ? eq.coordinate : eq.coordinate + "_ddot";
        std::size_t s = 0;
        while (s < count && model.coordinates[s].name != eq.coordinate) ++s;
        if (s == count) {
            const std::string near = nearest_name(key, names);
            throw InputError(eq.pos, fmt::format("'{}' names no declared coordinate{}", key,
                                                 near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (seen[s]) throw InputError(eq.pos, fmt::format("a second equation for coordinate '{}'", eq.coordinate));
        seen[s] = true;
        const std::string what = given.fundamental ? fmt::format("the fundamental form's equation for '{}'", eq.coordinate)
                                                   : fmt::format("the acceleration '{}'", key);
        n.expressions[s] = symbols.parse(eq.value, given.fundamental ? any_symbol : phase, what);
        n.positions[s] = eq.value.pos;
        if (given.fundamental) {
            for (const auto& c : model.coordinates) {
                if (!n.expressions[s].has(c.q_ddot)) continue;
                if (!n.expressions[s].diff(c.q_ddot).expand().has(c.q_ddot)) continue;
                throw InputError(eq.value.pos, fmt::format("{} is not linear in the accelerations ('{}' appears "
                                                           "non-linearly); the fundamental form is A(t,q,q̇) q̈ + "
                                                           "B(t,q,q̇)",
                                                           what, c.name + "_ddot"));
            }
        }
    }
    for (std::size_t s = 0; s < count; ++s)
        if (!seen[s])
            throw InputError(given.pos, fmt::format("[newtonian{}] gives no equation for coordinate '{}' (expected "
                                                    "'{} = \"...\"')",
                                                    given.fundamental ? ".fundamental" : "", model.coordinates[s].name,
                                                    names[s]));
    return n;
}

// The value of an expression of the parameters at their defaults (for the initial state).
double at_defaults(const ex& e, const Model& model, const scene::Expr& where, const std::string& what) {
    const auto value = real_value(e, model.parameter_defaults());
    if (!value) throw InputError(where.pos, fmt::format("{} does not evaluate to a real number", what));
    return value->to_double();
}

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

// The state names every rigid-body formulation writes through (events and integrals use them),
// and each formulation's own.
constexpr std::array<const char*, 6> rigid_physical_names{"p", "q", "r", "gamma1", "gamma2", "gamma3"};

std::vector<std::string> rigid_formulation_state_names(scene::RigidFormulationKind kind) {
    using K = scene::RigidFormulationKind;
    switch (kind) {
        case K::euler_poisson: return {};
        case K::quaternion: return {"e0", "e1", "e2", "e3"};
        case K::euler_angles: return {"phi", "theta", "psi"};
        case K::andoyer_deprit: return {"l", "g", "h", "L", "G", "H"};
    }
    return {};
}

// The body → space quaternion of the ZXZ rotation R_z(φ) R_x(θ) R_z(ψ) (Goldstein, Classical
// Mechanics, 3rd ed., §4.4; the Euler parameters of each factor multiplied in order).
std::array<double, 4> zxz_quaternion(double phi, double theta, double psi) {
    const double a = (phi + psi) / 2, b = (phi - psi) / 2;
    return {std::cos(theta / 2) * std::cos(a), std::sin(theta / 2) * std::cos(b), std::sin(theta / 2) * std::sin(b),
            std::cos(theta / 2) * std::sin(a)};
}

// The initial Andoyer-Deprit variables, at the defaults. They are singular where the angular
// momentum is along body axis 3 or along the vertical (runtime/rigid/andoyer_deprit.hpp): refused
// there, a warning near (a thousandfold amplification of the angles' rates, as for the orbit
// elements).
std::array<double, 6> initial_andoyer(const RigidBody& body, const double (&I)[3][3], const GiNaC::exmap& defaults,
                                      std::vector<Warning>& warnings) {
    std::array<double, 3> K{};
    for (unsigned i = 0; i < 3; ++i) {
        const auto k = real_value(body.gyrostat[i], defaults);
        K[i] = k ? k->to_double() : 0.0;
        for (unsigned j = 0; j < 3; ++j) K[i] += I[i][j] * body.omega0[j];
    }
    try {
        const auto v = runtime::andoyer_from_body(K, body.vertical0);
        const double regularity = runtime::andoyer_regularity(v);
        if (regularity < 1e-3)
            warnings.push_back({body.formulation_pos,
                                fmt::format("the andoyer_deprit variables are nearly singular at the initial state "
                                            "(min(√(G² − L²), √(G² − H²))/G = {:.3g}): their angles' rates are "
                                            "amplified by its inverse",
                                            regularity)});
        return {v.l, v.g, v.h, v.L, v.G, v.H};
    } catch (const std::domain_error& e) {
        throw InputError(body.formulation_pos,
                         fmt::format("the andoyer_deprit formulation cannot describe the initial state: {}; use another "
                                     "formulation",
                                     e.what()));
    }
}

// [rigid_body]: the body's data as GiNaC objects, ω(0) and the initial attitude. With only γ(0)
// given, the attitude is the ZXZ one with φ = 0 (θ = acos γ3, ψ = atan2(γ1, γ2)): a heavy body's
// motion does not depend on its azimuth about the vertical, so any choice is as good.
void build_rigid_body(const scene::Scene& scene, SymbolTable& symbols, Model& model) {
    const scene::RigidBody& given = *scene.rigid_body;
    RigidBody body;
    body.pos = given.pos;
    body.formulation = given.formulation;
    body.formulation_pos = given.formulation_pos;
    body.initial_pos = given.initial_pos;
    std::vector<std::string> reserved(rigid_physical_names.begin(), rigid_physical_names.end());
    for (const auto& n : rigid_formulation_state_names(given.formulation)) reserved.push_back(n);
    for (const auto& p : scene.parameters)
        if (std::find(reserved.begin(), reserved.end(), p.name) != reserved.end())
            throw InputError(p.pos, fmt::format("parameter '{}' has the name of a state variable of the rigid body "
                                                "in the {} formulation ({}); rename the parameter",
                                                p.name, scene::name(given.formulation), fmt::join(reserved, ", ")));
    body.inertia = parse_inertia(symbols, given.inertia, given.inertia_pos, "the rigid body's inertia");
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j)
            if (i != j && !body.inertia(i, j).is_zero()) body.principal = false;
    // Positive definite at the defaults (Sylvester's criterion), as every body's inertia is.
    const GiNaC::exmap d = model.parameter_defaults();
    double m[3][3];
    {
        for (unsigned i = 0; i < 3; ++i)
            for (unsigned j = 0; j < 3; ++j) {
                const auto v = real_value(body.inertia(i, j), d);
                if (!v) throw InputError(given.inertia_pos, "the rigid body's inertia does not evaluate to real numbers");
                m[i][j] = v->to_double();
            }
        const double d1 = m[0][0], d2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        const double d3 = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                          m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if (!(d1 > 0 && d2 > 0 && d3 > 0))
            throw InputError(given.inertia_pos, "the rigid body's inertia is not positive definite at the default "
                                                "parameters (a body's inertia tensor about any point is)");
    }
    body.center = parse_vector(symbols, given.center, unsigned(SymbolKind::parameter), "the rigid body's mass centre");
    body.weight = symbols.parse(given.weight, unsigned(SymbolKind::parameter), "the rigid body's weight");
    if (given.gyrostatic_moment)
        body.gyrostat = parse_vector(symbols, *given.gyrostatic_moment, unsigned(SymbolKind::parameter),
                                     "the gyrostatic moment");
    for (std::size_t i = 0; i < 3; ++i) {
        body.omega[i] = symbols.declare(rigid_physical_names[i], SymbolKind::velocity);
        body.omega_rate[i] = symbols.declare(std::string(rigid_physical_names[i]) + "_dot", SymbolKind::acceleration);
        body.gamma[i] = symbols.declare(rigid_physical_names[3 + i], SymbolKind::coordinate);
    }
    if (given.formulation == scene::RigidFormulationKind::quaternion) {
        std::array<GiNaC::symbol, 4> e;
        for (std::size_t k = 0; k < 4; ++k) e[k] = symbols.declare(fmt::format("e{}", k), SymbolKind::coordinate);
        body.attitude = e;
    }
    body.omega0 = given.omega;
    double phi = 0, theta = 0, psi = 0;
    if (given.zxz) {
        phi = (*given.zxz)[0], theta = (*given.zxz)[1], psi = (*given.zxz)[2];
    } else {
        const auto& g = *given.vertical;
        theta = std::acos(std::clamp(g[2], -1.0, 1.0));
        psi = std::atan2(g[0], g[1]);
    }
    body.attitude0 = zxz_quaternion(phi, theta, psi);
    body.vertical0 = given.vertical ? *given.vertical
                                    : std::array<double, 3>{std::sin(theta) * std::sin(psi), std::sin(theta) * std::cos(psi),
                                                            std::cos(theta)};

    if (given.formulation == scene::RigidFormulationKind::euler_angles) {
        // Gimbal lock at the start: the rates of φ and ψ are undetermined where sin θ = 0.
        if (std::abs(std::sin(theta)) < 1e-6)
            throw InputError(given.initial_pos,
                             fmt::format("the euler_angles formulation cannot start at θ = {:.6g} (sin θ = 0: gimbal "
                                         "lock, where the ZXZ angles' rates are undetermined); use another formulation "
                                         "or tilt the initial attitude",
                                         theta));
        const auto& w = given.omega;
        const double phi_dot = (w[0] * std::sin(psi) + w[1] * std::cos(psi)) / std::sin(theta);
        const double theta_dot = w[0] * std::cos(psi) - w[1] * std::sin(psi);
        const double psi_dot = w[2] - phi_dot * std::cos(theta);
        const double q0[3] = {phi, theta, psi}, u0[3] = {phi_dot, theta_dot, psi_dot};
        const char* names[3] = {"phi", "theta", "psi"};
        for (int k = 0; k < 3; ++k)
            model.coordinates.push_back({names[k], symbols.declare(names[k], SymbolKind::coordinate),
                                         symbols.declare(std::string(names[k]) + "_dot", SymbolKind::velocity),
                                         symbols.declare(std::string(names[k]) + "_ddot", SymbolKind::acceleration),
                                         q0[k], u0[k]});
        // L = ½ ωᵀIω + k·ω − P r_c·γ with ω and γ in the angles (Goldstein, Classical Mechanics,
        // 3rd ed., §4.9, eq. 4.87, for the ZXZ angles; γ = (sin θ sin ψ, sin θ cos ψ, cos θ)): the
        // Lagrangian chapter derives the rest.
        const ex th = model.coordinates[1].q, ps = model.coordinates[2].q;
        const ex phd = model.coordinates[0].q_dot, thd = model.coordinates[1].q_dot, psd = model.coordinates[2].q_dot;
        const Vec3 omega{phd * sin(th) * sin(ps) + thd * cos(ps), phd * sin(th) * cos(ps) - thd * sin(ps),
                         phd * cos(th) + psd};
        const Vec3 vertical{sin(th) * sin(ps), sin(th) * cos(ps), cos(th)};
        for (unsigned i = 0; i < 3; ++i) {
            body.in_angles[body.omega[i]] = omega[i];
            body.in_angles[body.gamma[i]] = vertical[i];
        }
        ex T = 0, V = 0;
        for (unsigned i = 0; i < 3; ++i) {
            for (unsigned j = 0; j < 3; ++j) T += body.inertia(i, j) * omega[i] * omega[j] / 2;
            T += body.gyrostat[i] * omega[i];
            V += body.weight * body.center[i] * vertical[i];
        }
        model.kinetic_energy = T;
        model.potential = V;
    }
    if (given.formulation == scene::RigidFormulationKind::andoyer_deprit)
        body.andoyer0 = initial_andoyer(body, m, d, model.warnings);
    model.kinetic_pos = given.pos;
    model.rigid = std::move(body);
}

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

}  // namespace

// The value of `e` at `values`, with the size of its terms (Σ |term| of its sum) so that a
// residual is judged relative to the magnitudes that cancel in it; NaN where it is undefined. The
// terms as written, not expanded: a scene's power of a sum could expand past any memory.
static std::pair<double, double> value_and_size(const ex& e, const GiNaC::exmap& values) {
    const auto number = [&](const ex& term) {
        const auto value = real_value(term, values);
        return value ? value->to_double() : std::numeric_limits<double>::quiet_NaN();
    };
    double size = 0.0;
    if (GiNaC::is_a<GiNaC::add>(e))
        for (const ex& term : e) size += std::abs(number(term));
    else
        size = std::abs(number(e));
    return {number(e), size};
}

// `e` at the initial state (t = 0, q0, q̇0, the quasi-velocities' initial values) and the
// parameters' defaults.
static std::pair<double, double> at_initial_state(const ex& e, const Model& model) {
    GiNaC::exmap values = model.parameter_defaults();
    values[model.t] = 0;
    for (const auto& c : model.coordinates) {
        values[c.q] = GiNaC::numeric(c.initial);
        values[c.q_dot] = GiNaC::numeric(c.rate);
    }
    for (const auto& v : model.quasi_velocities) values[v.symbol] = GiNaC::numeric(v.initial);
    return value_and_size(e, values);
}

// Whether `e` vanishes identically in t, q, q̇ (parameters at their defaults): GiNaC's own zero
// test, else zero to round-off at three fixed pseudo-random states. Numbers, not normal(): a
// scene's power of a sum would make normal() expand it.
static bool vanishes_identically(const ex& e, const Model& model) {
    if (e.is_zero()) return true;
    std::mt19937_64 random(0x11ea4);  // fixed: the same scene gets the same verdict
    std::uniform_real_distribution<double> uniform(0.5, 1.5);
    for (int k = 0; k < 3; ++k) {
        GiNaC::exmap values = model.parameter_defaults();
        values[model.t] = GiNaC::numeric(uniform(random));
        for (const auto& c : model.coordinates) {
            values[c.q] = GiNaC::numeric(uniform(random));
            values[c.q_dot] = GiNaC::numeric(uniform(random));
        }
        for (const auto& v : model.quasi_velocities) values[v.symbol] = GiNaC::numeric(uniform(random));
        const auto [value, size] = value_and_size(e, values);
        // Not finite (a pole, an overflow): not shown to vanish.
        if (!std::isfinite(value) || !std::isfinite(size) || std::abs(value) > 1e-9 * (1.0 + size)) return false;
    }
    return true;
}

// The velocities u (the coordinates' rates, then a free carrier's quasi-velocities).
static std::vector<GiNaC::symbol> velocity_symbols(const Model& model) {
    std::vector<GiNaC::symbol> rates;
    for (const auto& c : model.coordinates) rates.push_back(c.q_dot);
    for (const auto& v : model.quasi_velocities) rates.push_back(v.symbol);
    return rates;
}

// ḟ = ∂_t f + Σ ∂f/∂q_s q̇_s: a holonomic row's velocity form.
static ex velocity_form(const ex& f, const Model& model) {
    ex phi = f.diff(model.t);
    for (const auto& c : model.coordinates) phi += f.diff(c.q) * c.q_dot;
    return phi;
}

// A kinematic row φ (bilateral or unilateral, §6.7) must read B(q, t) u + b(q, t): every second
// derivative in the rates vanishes identically, and it holds at least one rate. `what` names the row
// ("kinematic constraint 'blade'"); `holonomic_key` is the key a relation of the coordinates alone
// is written with.
static void check_linear_in_rates(const ex& phi, const Model& model, const SourcePos& pos, const std::string& what,
                                  const char* holonomic_key) {
    const std::vector<GiNaC::symbol> rates = velocity_symbols(model);
    bool has_rate = false;
    for (std::size_t j = 0; j < rates.size(); ++j) {
        const ex first_derivative = phi.diff(rates[j]);
        if (!vanishes_identically(first_derivative, model)) has_rate = true;
        for (std::size_t k = j; k < rates.size(); ++k)
            if (!vanishes_identically(first_derivative.diff(rates[k]), model))
                throw InputError(pos, fmt::format("the {} is not linear in the rates: its second derivative in '{}' and "
                                                  "'{}' does not vanish (a row must read B(q, t) q_dot + b(q, t) = 0)",
                                                  what, rates[j].get_name(), rates[k].get_name()));
    }
    if (!has_rate)
        throw InputError(pos, fmt::format("the {} holds no rate (q_dot); a relation of the coordinates alone is written "
                                          "{} = \"...\"",
                                          what, holonomic_key));
}

// A row's expression at the initial state and the defaults, with the size of its terms; refused at
// `pos` when it is not a real number there. `level` names it in the message ("f(q0, 0)").
static std::pair<double, double> row_at_initial_state(const ex& e, const Model& model, const SourcePos& pos,
                                                      const std::string& name, const char* noun, const char* level) {
    const auto value_size = at_initial_state(e, model);
    if (!std::isfinite(value_size.first))
        throw InputError(pos, fmt::format("the {} '{}' does not evaluate to a real number at the initial state ({})", noun,
                                          name, level));
    return value_size;
}

// [[constraint]] rows: parsed with the scene's symbols and checked (Mei, §6.6; Lur'e, ch. 2).
static void build_constraints(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    if (scene.constraints.empty()) return;
    const scene::Constraint& first = scene.constraints.front();
    if (scene.newtonian)
        throw InputError(first.expression.pos,
                         "[[constraint]] is not supported in a [newtonian] scene: its equations are given, so there "
                         "are no energies for the reactions to enter; give the constrained system by [lagrangian] "
                         "or [[body]]");
    if (scene.orbit)
        throw InputError(first.expression.pos,
                         "[[constraint]] is not supported in an [orbit] scene: an orbit is a free point mass; give "
                         "a constrained system by [lagrangian] or [[body]]");
    for (const auto& given : scene.constraints) {
        Constraint row;
        row.name = given.name;
        row.holonomic = given.holonomic;
        row.pos = given.expression.pos;
        row.stabilization = given.stabilize == "baumgarte" ? ConstraintStabilization::baumgarte
                            : given.stabilize == "none"    ? ConstraintStabilization::none
                                                           : ConstraintStabilization::project;
        row.alpha = given.alpha;
        row.beta = given.beta;
        const std::string what = fmt::format("the {} constraint '{}'{}", given.holonomic ? "holonomic" : "kinematic",
                                             given.name,
                                             given.holonomic ? " (a function of the coordinates and t only; give a "
                                                               "row in the rates as kinematic = \"...\")"
                                                             : "");
        row.expression = symbols.parse(given.expression, given.holonomic ? configuration : phase, what);
        // The velocity-level row φ: ḟ = ∂_t f + Σ ∂f/∂q_s q̇_s for a holonomic row.
        ex phi = row.expression;
        if (row.holonomic) phi = velocity_form(row.expression, model);
        else check_linear_in_rates(row.expression, model, row.pos, fmt::format("kinematic constraint '{}'", given.name),
                                   "holonomic");
        // The initial state must satisfy the row (positions and velocities), at the defaults.
        const auto check = [&](const ex& e, const char* level) {
            const auto [value, size] = row_at_initial_state(e, model, row.pos, given.name, "constraint", level);
            if (std::abs(value) > 1e-9 * size)
                throw InputError(row.pos, fmt::format("the initial state violates the constraint '{}': {} = {:.6g} "
                                                      "(not 0) at the initial values and the default parameters",
                                                      given.name, level, value));
        };
        if (row.holonomic) check(row.expression, "f(q0, 0)");
        check(phi, row.holonomic ? "df/dt(q0, q0_dot, 0)" : "phi(q0, q0_dot, 0)");
        model.constraints.push_back(std::move(row));
    }
}

// [[unilateral]] rows (Mei, ch. 6): a gap f(t, q) >= 0 or a velocity row φ(t, q, u) >= 0 (§6.7),
// parsed and checked as the [[constraint]] rows are, with Newton's restitution coefficient (a
// function of the parameters, 0 <= e <= 1 at the defaults), the initial state inside (f >= 0 or
// φ >= 0), and the contact method. The scene has refused the kinds of scene that take no rows.
static void build_unilateral(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    model.contact_method = scene.contact.method;
    model.theta = scene.contact.theta;
    model.impact_law = scene.contact.impact_law;
    model.impact_law_pos = scene.contact.impact_law_pos;
    model.contact_method_pos = scene.contact.method_pos;
    for (const auto& given : scene.unilateral) {
        Unilateral row;
        row.name = given.name;
        row.holonomic = given.holonomic;
        row.pos = given.expression.pos;
        row.restitution_pos = given.restitution.pos;
        const std::string what =
            given.holonomic ? fmt::format("the gap of the unilateral constraint '{}' (a function of the coordinates and t "
                                          "only; give a row in the rates as velocity = \"...\")",
                                          given.name)
                            : fmt::format("the unilateral velocity constraint '{}'", given.name);
        row.expression = symbols.parse(given.expression, given.holonomic ? configuration : phase, what);
        if (!given.holonomic)
            check_linear_in_rates(row.expression, model, row.pos,
                                  fmt::format("unilateral velocity constraint '{}'", given.name), "gap");
        // Newton's coefficient: parameters only, in [0, 1] at their defaults.
        row.restitution = symbols.parse(given.restitution, unsigned(SymbolKind::parameter),
                                        fmt::format("the restitution of the unilateral constraint '{}'", given.name));
        row.restitution_default = at_defaults(row.restitution, model, given.restitution,
                                              fmt::format("the restitution of '{}'", given.name));
        if (!runtime::contact::valid_restitution(row.restitution_default))
            throw InputError(given.restitution.pos,
                             fmt::format("the restitution of the unilateral constraint '{}' is {:.6g} at the default "
                                         "parameters; Newton's coefficient must lie between 0 (plastic) and 1 (elastic)",
                                         given.name, row.restitution_default));
        // The initial state inside the admissible set: f(q0, 0) >= 0 (or φ >= 0), to round-off.
        const char* level = given.holonomic ? "f(q0, 0)" : "phi(q0, q0_dot, 0)";
        const auto [value, size] =
            row_at_initial_state(row.expression, model, row.pos, given.name, "unilateral constraint", level);
        if (value < -1e-9 * size)
            throw InputError(row.pos, fmt::format("the initial state violates the unilateral constraint '{}': {} = {:.6g} "
                                                  "(must be >= 0) at the initial values and the default parameters",
                                                  given.name, level, value));
        model.unilateral.push_back(std::move(row));
    }
}

// [[program]] rows (Mei, ch. 3): the relation parsed in the phase-space symbols, its kind read off
// the symbols it holds, the law checked against the kind (φ̇ + κφ = 0 is first order: a relation
// of the coordinates would need its rate given too; ω̈ + 2αω̇ + β²ω = 0 is second order: a relation
// holding the rates would need their rates), and the control's directions.
static void build_programs(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    for (const auto& given : scene.programs) {
        Program row;
        row.name = given.name;
        row.pos = given.constraint.pos;
        row.erugin_pos = given.erugin_pos;
        row.control_pos = given.control_pos;
        row.expression = symbols.parse(given.constraint, phase, fmt::format("the program '{}'", given.name));
        row.configuration = true;
        for (const auto& c : model.coordinates)
            if (row.expression.has(c.q_dot)) row.configuration = false;
        bool moves = false;
        for (const auto& c : model.coordinates) moves = moves || row.expression.has(c.q) || row.expression.has(c.q_dot);
        if (model.rigid) {
            // A rigid body (Mei §3.2): programs on the angular velocity, φ(ω, attitude, t) = 0, or on
            // the attitude alone, ω(γ, e, t) = 0 (configuration space: e the quaternion formulation's
            // attitude, for an error quaternion), realised by torques in Euler's equations, in the
            // formulations whose state holds ω itself.
            const auto kind = model.rigid->formulation;
            if (kind != scene::RigidFormulationKind::euler_poisson && kind != scene::RigidFormulationKind::quaternion)
                throw InputError(row.pos, fmt::format("the program '{}' on a rigid body needs the euler_poisson or "
                                                      "quaternion formulation (the state must hold omega = (p, q, r)), "
                                                      "not {}",
                                                      given.name, scene::name(kind)));
            bool rates = false;
            for (const auto& w : model.rigid->omega) rates = rates || row.expression.has(w);
            for (const auto& g : model.rigid->gamma) moves = moves || row.expression.has(g);
            if (model.rigid->attitude)
                for (const auto& e : *model.rigid->attitude) moves = moves || row.expression.has(e);
            moves = moves || rates;
            row.configuration = !rates;
        }
        if (!moves)
            throw InputError(row.pos, fmt::format("the program '{}' holds no coordinate or rate: a relation of t and the "
                                                  "parameters alone is not a motion a control can realise",
                                                  given.name));
        row.closed_loop = given.closed_loop;
        row.alpha = given.alpha;
        row.beta = given.beta;
        row.kappa = given.kappa;
        if (given.closed_loop && row.configuration && given.phase_law)
            throw InputError(given.erugin_pos,
                             fmt::format("the program '{}' is a relation of the coordinates (configuration space), so "
                                         "Erugin's law is of second order: give erugin = {{ alpha = ..., beta = ... }} "
                                         "(omega_ddot + 2 alpha omega_dot + beta^2 omega = 0), not kappa",
                                         given.name));
        if (given.closed_loop && !row.configuration && !given.phase_law)
            throw InputError(given.erugin_pos,
                             fmt::format("the program '{}' holds rates (phase space), so Erugin's law is of first order: "
                                         "give erugin = {{ kappa = ... }} (phi_dot + kappa phi = 0), not alpha and beta",
                                         given.name));
        if (given.control == "directions") {
            row.control = ProgramControl::directions;
            row.direction.assign(model.coordinates.size(), 0);
            for (const auto& [coordinate, text] : given.directions) {
                std::size_t k = 0;
                while (model.coordinates[k].name != coordinate) ++k;
                row.direction[k] = symbols.parse(
                    text, phase, fmt::format("the control direction of program '{}' on '{}'", given.name, coordinate));
            }
        } else if (given.control == "moment") {
            row.control = ProgramControl::moment;
            for (const auto& m : given.moment)
                row.direction.push_back(symbols.parse(
                    m, unsigned(SymbolKind::parameter),
                    fmt::format("the control moment of program '{}' (body axes; parameters only)", given.name)));
        } else if (given.control == "actuated") {
            row.control = ProgramControl::actuated;
            for (const auto& [coordinate, where] : given.actuated) {
                std::size_t k = 0;
                while (model.coordinates[k].name != coordinate) ++k;
                row.actuated.push_back(k);
            }
        }
        model.programs.push_back(std::move(row));
    }
}

// [[constraint]] rows beside [[program]] rows (Mei ch. 3 with §6.6's rows): a bilateral row is an
// ideal program whose law is its stabilisation — Baumgarte's f̈ + 2αḟ + β²f = 0 is Erugin's law with
// Galiullin's gains, φ̇ + αφ = 0 for a kinematic row, the open loop for "none" — so the reactions μ
// and the controls λ are solved together from M u̇ = f + Wᵀ μ + D λ, W u̇ = c_W, Ā u̇ = c (the
// control chapter's kernel; Udwadia & Kalaba, Analytical Dynamics, 1996, ch. 2, treat constraints
// and programs alike). The rows go first, keeping their names (lambda_<name> is μ). "project" is
// the constrained kernel's own step after each step, which the controlled kernel has not: refused.
static void constraints_as_programs(const scene::Scene& scene, Model& model) {
    std::vector<Program> rows;
    for (std::size_t a = 0; a < model.constraints.size(); ++a) {
        const Constraint& c = model.constraints[a];
        const scene::Constraint& given = scene.constraints[a];
        if (c.stabilization == ConstraintStabilization::project)
            throw InputError(given.stabilize_pos,
                             fmt::format("the constraint '{}' beside [[program]] rows is solved with them as one more "
                                         "ideal row, whose law is its stabilisation: give stabilize = {{ alpha = ..., "
                                         "beta = ... }} (Baumgarte's law, realised exactly as Erugin's) or \"none\"; "
                                         "\"project\" (the default) is the constrained kernel's step, which a "
                                         "controlled kernel does not take",
                                         c.name));
        for (const auto& p : model.programs)
            if (p.name == c.name)
                throw InputError(p.pos, fmt::format("the program '{}' has the name of a [[constraint]] row; the two "
                                                    "are solved together and their outputs (lambda_{}) would clash",
                                                    p.name, p.name));
        Program row;
        row.name = c.name;
        row.configuration = c.holonomic;
        row.expression = c.expression;
        row.closed_loop = c.stabilization == ConstraintStabilization::baumgarte;
        row.alpha = c.holonomic ? c.alpha : 0.0;
        row.beta = c.holonomic ? c.beta : 0.0;
        row.kappa = c.holonomic ? 0.0 : c.alpha;
        row.control = ProgramControl::ideal;
        row.pos = row.control_pos = c.pos;
        row.erugin_pos = given.stabilize_pos;
        rows.push_back(std::move(row));
    }
    rows.insert(rows.end(), model.programs.begin(), model.programs.end());
    model.programs = std::move(rows);
    model.constraints.clear();
}

Model build_model(const scene::Scene& scene) {
    Model model;
    model.name = scene.name;
    model.struct_name = scene::struct_name(scene.name);
    model.summary = scene.summary;
    model.source = scene.path;
    model.simulate = scene.simulate;
    model.hamiltonian = scene.formulation == "hamiltonian";
    model.inverse = scene.inverse;

    SymbolTable symbols;
    model.t = symbols.declare("t", SymbolKind::time);
    for (const auto& p : scene.parameters)
        model.parameters.push_back({p.name, symbols.declare(p.name, SymbolKind::parameter), p.value});
    if (scene.orbit) build_orbit(scene, symbols, model);
    if (scene.rigid_body) build_rigid_body(scene, symbols, model);
    for (const auto& c : scene.coordinates) {
        model.coordinates.push_back({c.name, symbols.declare(c.name, SymbolKind::coordinate),
                                     symbols.declare(c.name + "_dot", SymbolKind::velocity),
                                     symbols.declare(c.name + "_ddot", SymbolKind::acceleration), c.initial,
                                     c.rate});
    }

    if (scene.carrier) {
        const auto& c = *scene.carrier;
        if (c.motion == "free") {
            if (scene.effects.given)
                throw InputError(scene.effects.keep_pos.empty() ? c.motion_pos : scene.effects.keep_pos.front(),
                                 "[effects] cannot drop terms of a free carrier's equations: its motion follows from "
                                 "all of them");
            build_free_carrier(c, scene.forces, symbols, model);
        } else {
            Carrier carrier;
            carrier.angular_velocity =
                parse_vector(symbols, c.angular_velocity, time_and_parameters, "the carrier's angular velocity");
            carrier.pole_velocity = parse_vector(symbols, c.pole_velocity, time_and_parameters, "the carrier's pole velocity");
            add_carrier_mass_and_loads(c, scene.forces, symbols, model, carrier);
            model.carrier = std::move(carrier);
        }
    }
    for (const auto& b : scene.bodies) {
        Particle body;
        body.name = b.name;
        body.mass = parse_mass(symbols, b, model);
        body.position = parse_vector(symbols, b.position, configuration, fmt::format("the position of body '{}'", b.name));
        if (!b.inertia.empty()) {
            body.rigid = true;
            body.inertia = parse_inertia(symbols, b.inertia, b.inertia_pos, fmt::format("the inertia of body '{}'", b.name));
            for (const auto& r : b.orientation)
                body.orientation.emplace_back(
                    r.axis, symbols.parse(r.angle, configuration,
                                          fmt::format("an orientation angle of body '{}'", b.name)));
        }
        model.particles.push_back(std::move(body));
    }
    if (!scene.bodies.empty()) model.kinetic_pos = scene.bodies.front().pos;

    if (scene.lagrangian) {
        model.kinetic_energy = symbols.parse(scene.lagrangian->kinetic, phase, "the kinetic energy T");
        model.potential = symbols.parse(scene.lagrangian->potential, phase, "the potential V");
        model.kinetic_pos = scene.lagrangian->kinetic.pos;
    }
    // Potentials from [lagrangian] and [forces] add up.
    if (scene.forces.potential) model.potential += symbols.parse(*scene.forces.potential, phase, "the potential");

    model.generalized_forces.assign(model.coordinates.size(), ex(0));
    for (const auto& q : scene.forces.generalized) {
        std::size_t s = 0;
        while (s < model.coordinates.size() && model.coordinates[s].name != q.coordinate) ++s;
        if (s == model.coordinates.size()) {
            std::vector<std::string> names;
            for (const auto& c : model.coordinates) names.push_back(c.name);
            const std::string near = nearest_name(q.coordinate, names);
            throw InputError(q.pos, fmt::format("generalized force for '{}', which is not a declared coordinate{}",
                                                q.coordinate,
                                                near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        model.generalized_forces[s] =
            symbols.parse(q.value, phase, fmt::format("the generalized force on '{}'", q.coordinate));
    }
    // An orbit's non-conservative accelerations are its generalized forces per unit mass
    // (x, y, z are Cartesian, so Q_s = a · ∂r/∂q_s = a_s).
    if (model.orbit)
        for (std::size_t s = 0; s < 3; ++s) model.generalized_forces[s] = model.orbit->acceleration[s];

    if (scene.reference) {
        // The reference is the Lagrangian state (q, q_dot); kernels of other states would be judged
        // against values of different variables.
        if (model.hamiltonian)
            throw InputError(scene.reference->pos,
                             "[reference] gives q and q_dot, but [formulation] kind = \"hamiltonian\" integrates (q, p)");
        if (model.free_carrier())
            throw InputError(scene.reference->pos,
                             "[reference] is not available with a free carrier (its state also holds the carrier's "
                             "velocities and attitude)");
        // In state order, whatever the file order.
        auto parse_reference = [&](const std::string& state) {
            for (const auto& v : scene.reference->values)
                if (v.state == state)
                    return symbols.parse(v.value, time_and_parameters,
                                         fmt::format("the reference value of '{}'", state));
            throw InputError(scene.reference->pos, fmt::format("[reference] gives no value for '{}'", state));
        };
        for (const auto& c : model.coordinates) model.reference.push_back(parse_reference(c.name));
        for (const auto& c : model.coordinates) model.reference.push_back(parse_reference(c.name + "_dot"));
    }

    for (const auto& e : scene.events)
        model.events.push_back({e.name, symbols.parse(e.when, phase, fmt::format("event '{}'", e.name)),
                                e.direction == "up" ? 1 : (e.direction == "down" ? -1 : 0), e.terminal, e.pos});
    // Every orbit ends where it reaches the central body's surface: a terminal event, located
    // like any other, instead of integrating on into the body.
    if (model.orbit) {
        for (const auto& e : model.events)
            if (e.name == "re_entry")
                throw InputError(e.pos, "'re_entry' is the orbit's own event (r = radius); give this event another name");
        model.events.push_back({"re_entry", model.orbit->r - model.orbit->radius, -1, true, scene.orbit->pos});
    }

    if (scene.newtonian) {
        model.newtonian = build_newtonian(symbols, *scene.newtonian, model);
        model.kinetic_pos = scene.newtonian->pos;
    }

    build_constraints(scene, symbols, model);
    build_unilateral(scene, symbols, model);
    build_programs(scene, symbols, model);
    if (!model.programs.empty()) constraints_as_programs(scene, model);

    if (scene.effects.given && !scene.orbit) {  // an orbit scene's names are perturbations (build_orbit)
        model.keep.fill(false);
        for (const auto& e : scene.effects.keep)
            for (Effect k : all_effects)
                if (e == name(k)) model.keep[static_cast<int>(k)] = true;
    }
    return model;
}

}  // namespace eomc::model
