// The rigid kind ([rigid_body]; Mei, ch. 5): a heavy body or gyrostat about a fixed point, its
// initial attitude in each formulation, and its attitude's rates.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "eomc/runtime/rigid/andoyer_deprit.hpp"
#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

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

namespace {

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

}  // namespace

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
    body.inertia_pos = given.inertia_pos;
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

}  // namespace eomc::model
